"""URDF robots among boxes (planners.collision): pairs, broad phase against the pairwise reference, the
C-space protocol and the segment checker."""

import coal
import numpy as np
import pinocchio as pin
import pytest

from planners.collision import Box, CollisionChecker, UrdfCSpace, bisection_order, example_robot_srdf
from planners.sampling import edge_is_free
from rigid_body.robots import load


@pytest.fixture(scope="module")
def panda_checker():
    boxes = [Box([0.6, 0.0, 0.20], [0.5, 1.2, 0.04], "table"), Box([0.6, 0.0, 0.60], [0.5, 1.2, 0.03], "shelf")]
    return CollisionChecker(load("panda"), boxes, srdf=example_robot_srdf("panda"))


def test_broad_phase_agrees_with_the_pairwise_check(panda_checker):
    space = UrdfCSpace(panda_checker)
    rng = np.random.default_rng(3)
    Q = np.array([space.sample(rng) for _ in range(400)])
    broad = np.array([panda_checker.in_collision(q) for q in Q])
    pairwise = np.array([panda_checker.in_collision_pairwise(q) for q in Q])
    assert np.array_equal(broad, pairwise)
    assert 0.05 < broad.mean() < 0.95          # both answers occur


def test_a_box_collision_matches_coal_called_directly(panda_checker):
    """Robot–box contacts from the checker = coal.collide on the hand's shapes and the table, by hand."""
    robot = panda_checker.robot
    geom = robot.collision_model
    data = geom.createData()
    table = coal.Box(0.5, 1.2, 0.04)
    M_table = pin.SE3(np.eye(3), np.array([0.6, 0.0, 0.20]))
    rng = np.random.default_rng(5)
    space = UrdfCSpace(panda_checker)
    hits = 0
    for _ in range(150):
        q = space.sample(rng)
        pin.updateGeometryPlacements(robot.model, robot.data, geom, data, q)
        direct = False
        for k, g in enumerate(geom.geometryObjects):
            if g.parentJoint == 0:
                continue
            res = coal.CollisionResult()
            direct |= coal.collide(g.geometry, data.oMg[k], table, M_table, coal.CollisionRequest(), res)
        pairs = panda_checker.colliding_pairs(q)
        assert direct == any("table" in b for _, b in pairs)
        hits += direct
    assert hits > 0


def test_srdf_and_adjacency_filter_the_self_collision_pairs(panda_checker):
    unfiltered = CollisionChecker(panda_checker.robot, [], srdf=None)
    assert panda_checker.n_self_pairs < unfiltered.n_self_pairs
    names = [g.name for g in panda_checker.geom.geometryObjects]
    active = {(names[p.first], names[p.second]) for p in panda_checker.geom.collisionPairs}
    # the SRDF disables panda_hand–panda_link3 ("Never"), adjacency removes link3–link4
    assert ("panda_link3_0", "panda_hand_0") not in active and ("panda_hand_0", "panda_link3_0") not in active
    assert ("panda_link3_0", "panda_link4_0") not in active
    assert ("panda_link0_0", "panda_link5_0") in active


def test_anthropomorphic_tip_box_by_hand():
    """A 4 cm cube just beyond the tip of the stretched arm (a₂ + a₃ = 0.9 m along x at q = 0) is free, one
    on the tip is hit, and turning the waist by 90° (tip on the y axis) frees it again."""
    robot = load("anthropomorphic")
    far = CollisionChecker(robot, [Box([0.98, 0.0, 0.0], [0.04, 0.04, 0.04], "cube")])
    near = CollisionChecker(robot, [Box([0.90, 0.0, 0.0], [0.04, 0.04, 0.04], "cube")])
    assert not far.in_collision(np.zeros(3)) and near.in_collision(np.zeros(3))
    assert not near.in_collision(np.array([np.pi / 2, 0.0, 0.0]))
    assert near.box_clearance(np.array([np.pi / 2, 0.0, 0.0])) > 0.5


def test_static_base_touching_a_box_is_refused():
    with pytest.raises(ValueError, match="fixed shape"):
        CollisionChecker(load("panda"), [Box([0.0, 0.0, 0.0], [0.3, 0.3, 0.1], "slab")])


def test_box_and_space_validation():
    with pytest.raises(ValueError, match="size"):
        Box([0, 0, 0], [1, -1, 1])
    with pytest.raises(ValueError, match="center"):
        Box([0, 0], [1, 1, 1])
    checker = CollisionChecker(load("anthropomorphic"), [])
    with pytest.raises(ValueError, match="resolution"):
        UrdfCSpace(checker, resolution=0.0)
    with pytest.raises(ValueError, match="upper"):
        UrdfCSpace(checker, lower=[0, 0, 0], upper=[1, -1, 1])


def test_bisection_order_is_a_permutation_ends_first():
    for n in (1, 2, 3, 10, 33):
        order = bisection_order(n)
        assert sorted(order.tolist()) == list(range(n))
        if n >= 2:
            assert order[:2].tolist() == [0, n - 1]


def test_segment_checker_resolution_and_early_exit():
    checker = CollisionChecker(load("anthropomorphic"), [Box([0.55, 0.0, 0.03], [0.15, 0.15, 0.94], "pillar")])
    space = UrdfCSpace(checker, resolution=0.05)
    a, b = np.array([0.6, -0.3, 0.9]), np.array([-0.6, -0.3, 0.9])
    P = space.local_path(a, b)
    assert np.abs(np.diff(P, axis=0)).max() <= 0.05 + 1e-12 and len(P) == 25
    inside = [space.is_valid(q) for q in P]
    assert not all(inside) and inside[0] and inside[-1]    # the pillar cuts the straight segment
    checker.calls = 0
    assert not edge_is_free(space, a, b)
    assert checker.calls < len(P)                           # stopped at the first collision
    assert edge_is_free(space, a, a + [0.04, 0.0, 0.0])


def test_wrong_configuration_size_is_named():
    space = UrdfCSpace(CollisionChecker(load("anthropomorphic"), []))
    with pytest.raises(ValueError, match="`q` must have shape"):
        space.is_valid(np.zeros(2))


def test_overlapping_boxes_are_not_a_collision():
    """Box–box contacts are not pairs: two boxes overlapping far from the arm leave q free (broad phase too)."""
    checker = CollisionChecker(load("anthropomorphic"), [Box([2.0, 0.0, 0.0], [0.4, 0.4, 0.4], "a"),
                                                         Box([2.1, 0.0, 0.0], [0.4, 0.4, 0.4], "b")])
    q = np.zeros(3)
    assert not checker.in_collision(q) and not checker.in_collision_pairwise(q)
    assert checker.box_clearance(q) == pytest.approx(2.0 - 0.2 - 0.918, abs=1e-6)   # tip box face at 0.918 m
