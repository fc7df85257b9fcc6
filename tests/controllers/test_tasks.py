"""Chapter-6 action level: programs, primitives, errors naming the step, contact model, paths."""

import numpy as np
import pytest

from controllers.tasks import ActionExecutor, Step, TaskError, Workcell, fill_pallet_program, moveto
from planners.tasks import decompose_pick_and_place, pick_and_place_path
from rigid_body.task_space import joint_reference
from rigid_body.kinematics import direct_kinematics, inverse_kinematics_planar_3r, inverse_kinematics_scara
from rigid_body.robots import load

HOME = (0.5, -0.3, 0.3, 0.0)
FEED = (0.7, -0.3, 0.8, 0.0)


def test_fill_pallet_program_structure():
    prog = fill_pallet_program(HOME, FEED, (0.3, 0.3, 0.8, 0.0), 0.1, 0.05, 0.06, 1.0, 0.2, rows=2, columns=3,
                               up=(0, 0, -1))
    assert len(prog) == 2 + 6 * 9
    releases = [k for k, s in enumerate(prog) if s.primitive == "RELEASE"]
    slots = {tuple(np.round(prog[k - 1].location[:2], 9)) for k in releases}
    assert len(slots) == 6 and (0.35, 0.42) in slots
    assert all(prog[k - 1].location[2] == 0.8 and prog[k - 2].location[2] == pytest.approx(0.7) for k in releases)


def test_executor_places_object_and_names_failing_step():
    robot = load("scara")
    q0 = inverse_kinematics_scara(np.array(HOME))[0]
    cell = Workcell(FEED[:3])
    ex = ActionExecutor(robot, inverse_kinematics_scara, cell, q0)
    rec = ex.run([Step("NEW_OBJECT"), moveto(FEED, 0.5), Step("GRASP"), moveto((0.4, 0.3, 0.7, 0.3), 1.0),
                  Step("RELEASE")])
    np.testing.assert_allclose(rec.objects["object 1"], [0.4, 0.3, 0.7], atol=1e-3)
    with pytest.raises(TaskError, match=r"^step 0 RELEASE: nothing to release"):
        ex.run([Step("RELEASE")])
    with pytest.raises(TaskError, match=r"^step 1 MOVETO\(\[0.5, 0.5, 1.5"):
        ex.run([moveto(HOME, 1.0), moveto((0.5, 0.5, 1.5, 0.0), 1.0)])   # d3 beyond its range


def test_step_validation():
    with pytest.raises(ValueError, match="primitive"):
        Step("JUMP")
    with pytest.raises(ValueError, match="MOVETO"):
        Step("MOVETO")
    with pytest.raises(ValueError, match="velocity"):
        moveto(HOME, 0.0)




def test_joint_reference_is_consistent_with_finite_differences():
    robot = load("planar_3r")
    plan = decompose_pick_and_place((0.45, -0.2), (0.75, -0.2), (0.55, 0.65, -0.05), 0.05)
    law = pick_and_place_path(plan, (1.0, 1.5, 1.0), via_points=True, overlap=0.4)
    q0 = inverse_kinematics_planar_3r(np.array([0.45, -0.2, -np.pi / 2]))[0]
    ref = joint_reference(robot, inverse_kinematics_planar_3r, law, (0, 1), (-np.pi / 2,), (0, 1, 5), q0)
    dt = 1e-5
    for t in (0.3, 1.2, 2.0, 2.6):
        qm, qdm, _ = ref(t - dt)
        q, qd, qdd = ref(t)
        qp, qdp, _ = ref(t + dt)
        np.testing.assert_allclose(qd, (qp - qm) / (2 * dt), atol=1e-5)
        np.testing.assert_allclose(qdd, (qdp - qdm) / (2 * dt), atol=1e-3)
        np.testing.assert_allclose(direct_kinematics(robot, q)[:2, 3], law(t)[0][:2], atol=1e-12)
