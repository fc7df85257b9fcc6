"""Cost of the chapter-9 closed loops: simulated seconds per wall second, and one step's parts.

Run: ``python benchmarks/bench_force.py``. The table gives, for the two-link arm against the compliant plane
(MODEL-B), the time of one contact-plant derivative (forward dynamics + the environment's wrench),
one measurement and one call of the impedance (9.3) and hybrid (9.10) controllers; then the
simulated seconds per wall second of Problems 9.3 and 9.10 and of the Panda wall run (two 3.5 s
runs: impedance and hybrid force/motion control). Wall and CPU time are both printed: on the shared
2-core machine the wall time depends on the load, the process's CPU time much less.

Measured (CPU time, 2026-12-01, before → after the chapter-9 speed work; simulated s per CPU s; the
best of the runs — CPU time too varies by ±15 % with the load):

=====================================  ===========  ===========
run                                    before       after
=====================================  ===========  ===========
9.3 impedance control                  4.3x         8.1x
9.10 hybrid force/motion control       4.4x         8.2x
Panda on the stepped wall, hybrid      4.4x         6.2x
Panda on the stepped wall, impedance   2.7x         3.4x
=====================================  ===========  ===========

One call (CPU): contact-plant derivative 14.9 → 11.6 µs, measurement 7.7 → 5.4 µs, impedance law
102 → 33 µs, hybrid law 49 → 31 µs, one RK4 step 65 → 53 µs. The Pinocchio calls alone of one
simulated second of 9.3 (four RK4 stages of frame Jacobian + CRBA + nonlinear effects, the
measurement, the law's kinematics pass and RNEA per 1 ms sample) take 11.6 ms CPU (86x real time):
the rest is Python/NumPy work in the plant, the law and the loop (each NumPy call costs ~0.5–1 µs).
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np
import pinocchio as pin

from benchtools import per_call  # first: it puts the source tree (examples/) on sys.path
from controllers.compiled import fast_backend
from controllers.force import HybridForceMotionControl
from controllers.operational_space import OperationalInverseDynamics
from controllers.plants import ArmInContact
from controllers.scenes import PLANE_FRAME, PLANE_POINT, compliant_plane_9_16, panda_wall
from controllers.simulation import simulate
from examples.panda_wall_contact import T_PANDA, panda_hybrid, panda_impedance
from planners.paths import PathLaw, Segment
from planners.timing import trapezoidal_law
from rigid_body.kinematics import ELBOW_UP, inverse_kinematics_planar_2r
from rigid_body.robots import load
from rigid_body.task_space import selection_matrices


# The loops of Problems 9.3 and 9.10 (their data: the manual and the companion files i9_3, i9_10), built here from
# the library as a user would: the two-link arm with joint friction against the plane of Fig. 9.16.
F_V, T_D, T_C = 100.0, 2.5, 1e-3          # joint viscous friction [N·m·s/rad], run length [s], period [s]
K_HAT, LAMBDA_D = 4e3, -50.0              # 9.10: estimated plane stiffness [N/m], desired force along y_c [N]


def tra_5() -> PathLaw:
    """The companion's tra_5: a 0.2√2 m segment along x_c, trapezoidal with ṡ_c = 0.5 m/s over 1 s."""
    p_i = np.array([1.0 + 0.2 * np.cos(np.pi / 4), 0.0, 0.0])
    segment = Segment(p_i, p_i + np.array([0.2, 0.2, 0.0]))
    return PathLaw(segment, trapezoidal_law(0.0, segment.length, 1.0, 0.5))


def impedance_run(q0: np.ndarray):
    """9.3: impedance control with force feedback, M_d = 100, K_D = 1600, K_P = 5000 (the compiled loop)."""
    arm = load("planar_2r")
    plant = ArmInContact(arm, compliant_plane_9_16(), viscous_friction=F_V)
    ctrl = OperationalInverseDynamics(arm, 5000.0, 1600.0, tra_5(), rows=(0, 1), viscous_friction=F_V, inertia=100.0,
                                      force_feedback=True)
    return simulate(plant, ctrl, (0.0, T_D), plant.initial_state(q0), h=T_C, Ts=T_C, backend=fast_backend())


def hybrid_run():
    """9.10: hybrid force/motion control, velocity PI along x_c, force along y_c with the estimated stiffness."""
    arm = load("planar_2r")
    plant = ArmInContact(arm, compliant_plane_9_16(), viscous_friction=F_V)
    law = tra_5()

    def nu_reference(t: float) -> tuple[np.ndarray, np.ndarray]:
        _, pd, pdd = law(t)
        return (PLANE_FRAME.T @ pd[:2])[:1], (PLANE_FRAME.T @ pdd[:2])[:1]

    S_f, S_v = selection_matrices(("x",), PLANE_FRAME, axes=("x", "y"))
    C_hat = np.eye(2) / K_HAT
    ctrl = HybridForceMotionControl(arm, S_f, S_v, [LAMBDA_D], nu_reference, 16.0, 100.0, 16.0, 100.0,
                                    compliance=C_hat, stiffness=np.linalg.inv(C_hat),
                                    compliance_prime=PLANE_FRAME @ np.diag([0.0, 1.0 / K_HAT]) @ PLANE_FRAME.T,
                                    rows=(0, 1), viscous_friction=F_V)
    q0 = inverse_kinematics_planar_2r(PLANE_POINT)[ELBOW_UP]
    return simulate(plant, ctrl, (0.0, T_D), plant.initial_state(q0), h=T_C, Ts=T_C, backend=fast_backend())


def simulated_per_wall_second(label: str, run: Callable[[], object], simulated: float, target: bool = True) -> dict:
    """A row: simulated seconds per wall second (target ≥ 20 for the manual's loops), the CPU figure beside it
    (on a shared machine the wall time depends on the load, the process's CPU time much less)."""
    t0, c0 = time.perf_counter(), time.process_time()
    run()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return dict(measurement=f"{label} [simulated s / wall s]", rmpc=simulated / wall, reference=None,
                ref_name=f"{simulated / cpu:.1f} per CPU s", target=(">=", 20.0) if target else None)


def pinocchio_floor(robot, q: np.ndarray, qd: np.ndarray, tau: np.ndarray, fid: int, samples: int = 1000) -> float:
    """CPU seconds of the Pinocchio calls alone of ``samples`` 1 ms samples of a contact loop: four RK4 stages
    (frame Jacobian + CRBA + nonlinear effects; a robot with mimic rotor joints has no ABA), one measurement
    (frame Jacobian) and one law (kinematics pass with J̇q̇ + RNEA) — the floor of any Python loop on Pinocchio."""
    model, data, LWA = robot.model, robot.data, pin.LOCAL_WORLD_ALIGNED
    zero = np.zeros(robot.nv)
    c0 = time.process_time()
    for _ in range(samples):
        for _ in range(4):
            pin.computeFrameJacobian(model, data, q, fid, LWA)
            pin.crba(model, data, q)
            pin.nonLinearEffects(model, data, q, qd)
        pin.computeFrameJacobian(model, data, q, fid, LWA)
        pin.forwardKinematics(model, data, q, qd, zero)
        pin.computeJointJacobians(model, data)
        pin.updateFramePlacement(model, data, fid)
        pin.getFrameJacobian(model, data, fid, LWA)
        pin.getFrameClassicalAcceleration(model, data, fid, LWA)
        pin.rnea(model, data, q, qd, tau)
    return time.process_time() - c0


def rows(quick: bool = False) -> list[dict]:
    """One call of the contact plant and the two laws (µs, no target), the Pinocchio floor of one simulated
    second, and the closed loops of 9.3 and 9.10 (target ≥ 20× real time) and of the Panda wall example."""
    arm = load("planar_2r")
    plant = ArmInContact(arm, compliant_plane_9_16(), viscous_friction=F_V)
    q0 = inverse_kinematics_planar_2r(tra_5()(0.0)[0][:2])[ELBOW_UP]
    x = plant.initial_state(q0, [0.1, -0.2])
    u = np.array([10.0, 5.0])
    meas = plant.measure(0.0, x)
    imp = OperationalInverseDynamics(arm, 5000.0, 1600.0, tra_5(), rows=(0, 1), viscous_friction=F_V,
                                     inertia=100.0, force_feedback=True)
    S_f, S_v = selection_matrices(("x",), PLANE_FRAME, axes=("x", "y"))
    hyb = HybridForceMotionControl(arm, S_f, S_v, [-50.0], [0.1], 16, 100, 16, 100, compliance=np.eye(2) / K_HAT,
                                   rows=(0, 1), viscous_friction=F_V)
    out = [dict(measurement=f"9.x two-link arm on the plane: {label} [µs]", rmpc=per_call(f) * 1e6, reference=None,
                ref_name="", target=None)
           for label, f in (("contact-plant derivative", lambda: plant.derivative(0.0, x, u)),
                            ("measurement (q, q̇, sensed wrench)", lambda: plant.measure(0.0, x)),
                            ("impedance law (9.30)-(9.31)", lambda: imp(0.3, meas)),
                            ("hybrid force/motion law (9.77)-(9.81)", lambda: hyb(0.3, meas)))]
    floor = pinocchio_floor(arm, q0, np.array([0.1, -0.2]), u, plant._fid)
    out.append(dict(measurement="9.x Pinocchio calls alone, one simulated second [simulated s / CPU s]",
                    rmpc=1.0 / floor, reference=None, ref_name="the floor of any Python loop on Pinocchio", target=None))
    out.append(simulated_per_wall_second("9.3 impedance control", lambda: impedance_run(q0), T_D))
    out.append(simulated_per_wall_second("9.10 hybrid force/motion control", hybrid_run, T_D))
    if not quick:
        scene = panda_wall()
        out.append(simulated_per_wall_second("Panda on the stepped wall, hybrid", lambda: panda_hybrid(scene),
                                             T_PANDA, target=False))
        out.append(simulated_per_wall_second("Panda on the stepped wall, impedance",
                                             lambda: panda_impedance(scene, 0.021), T_PANDA, target=False))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
