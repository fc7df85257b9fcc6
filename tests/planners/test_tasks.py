"""Chapter-6 task and action levels: the pick-and-place decomposition and its C–D–E–F path."""

import numpy as np
import pytest

from planners.configuration_space import distance_to_box
from planners.timing import sample
from planners.tasks import decompose_pick_and_place, pick_and_place_path

A, B, OBSTACLE, CLEARANCE = (0.45, -0.2), (0.75, -0.2), (0.55, 0.65, -0.05), 0.05


def test_decomposition_points_clear_the_obstacle():
    plan = decompose_pick_and_place(A, B, OBSTACLE, CLEARANCE)
    assert plan.safe_height == pytest.approx(OBSTACLE[2] + CLEARANCE)
    np.testing.assert_allclose(plan.points["D"], [A[0], plan.safe_height])
    np.testing.assert_allclose(plan.points["E"], [B[0], plan.safe_height])
    assert [a.points for a in plan.actions][2] == ("C", "D", "E")


@pytest.mark.parametrize("via_points", [False, True])
def test_path_starts_and_ends_at_rest_and_keeps_the_clearance(via_points):
    plan = decompose_pick_and_place(A, B, OBSTACLE, CLEARANCE)
    law = pick_and_place_path(plan, (1.0, 1.5, 1.0), via_points=via_points, overlap=0.4)
    traj = sample(law, dt=1e-3)
    np.testing.assert_allclose(traj.q[0, :2], A, atol=1e-12)
    np.testing.assert_allclose(traj.q[-1, :2], B, atol=1e-12)
    for k in (0, -1):   # quintics: null velocity and acceleration at C and F
        assert np.abs(traj.qd[k]).max() < 1e-9 and np.abs(traj.qdd[k]).max() < 1e-9
    # independent reference: finite differences of the sampled position give the velocity
    np.testing.assert_allclose(np.gradient(traj.q, traj.t, axis=0)[1:-1], traj.qd[1:-1], atol=2e-3)
    d = distance_to_box(traj.q[:, :2], OBSTACLE)
    # path points stop at D and E (the whole clearance kept); via points cut the corners but stay off the box
    assert d.min() > (CLEARANCE - 1e-9 if not via_points else 0.0)


def test_pick_and_place_path_validation():
    plan = decompose_pick_and_place((0.3, -0.3), (0.7, -0.3), (0.45, 0.55, -0.1), 0.05)
    with pytest.raises(ValueError, match="`overlap`"):
        pick_and_place_path(plan, (1, 1, 1), via_points=True, overlap=2.0)
    with pytest.raises(ValueError, match="`middle`"):
        pick_and_place_path(plan, (1, 1, 1), middle="septic")
    with pytest.raises(ValueError, match="between A and B"):
        decompose_pick_and_place((0.3, -0.3), (0.4, -0.3), (0.45, 0.55, -0.1), 0.05)
