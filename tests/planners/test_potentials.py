"""Artificial potentials and navigation functions (planners.potentials)."""

import numpy as np
import pytest
from scipy.sparse.csgraph import dijkstra
from scipy.sparse import lil_matrix

from planners.configuration_space import Disc, Polygon, box
from planners.potentials import (AttractivePotential, PotentialField, RepulsivePotential, arm_joint_forces,
                                 gradient_descent, range_scan, reactive_repulsive_force, scan_segments,
                                 stationary_point, steepest_descent_path, wavefront)
from rigid_body.kinematics import frame_poses
from rigid_body.robots import load


def _fd_force(field, q, h=1e-6):
    return np.array([-(field.potential(q + d) - field.potential(q - d)) / (2 * h) for d in np.eye(2) * h]).T


@pytest.mark.parametrize("shape", [Disc([2, 1], 0.5), Polygon([[2, 0], [3, 0.5], [2.5, 1.5]])])
def test_force_is_minus_gradient(shape, rng):
    field = PotentialField(AttractivePotential([0, 0], 1.5, rho=1.0), (RepulsivePotential(shape, 0.7, 1.2),))
    Q = rng.uniform(-1, 5, (300, 2))
    eta = RepulsivePotential(shape).eta(Q)[0]
    Q = Q[(eta > 0.05) & (np.abs(eta - 1.2) > 1e-3) & (np.abs(np.linalg.norm(Q, axis=1) - 1.0) > 1e-3)]
    assert np.allclose(field.force(Q), _fd_force(field, Q), atol=1e-5)


def test_combined_attractive_force_is_continuous():
    att = AttractivePotential([0.0, 0.0], k_a=3.0, rho=0.5)
    assert att.k_b == pytest.approx(1.5)
    u = np.array([0.6, 0.8])
    for f in (att.force, att.potential):
        assert np.allclose(f(0.5 * (1 - 1e-10) * u), f(0.5 * (1 + 1e-10) * u), atol=1e-8)


def test_single_disc_saddle_and_two_disc_minimum():
    att = AttractivePotential([0, 0], 1.0)
    one = PotentialField(att, (RepulsivePotential(Disc([3, 0], 0.5)),))
    P = stationary_point(one, [3.9, 0.1])
    assert np.allclose(P, [4, 0]) and np.allclose(np.linalg.eigvalsh(one.hessian(P)), [-3, 33], atol=1e-4)
    two = PotentialField(att, tuple(RepulsivePotential(Disc([3, s * 0.8], 0.5)) for s in (1, -1)))
    run = gradient_descent(two.force, [3.67, 0.05], step=0.01, tol=1e-8)
    assert run.converged and np.linalg.norm(run.path[-1]) > 3
    assert np.all(np.linalg.eigvalsh(two.hessian(run.path[-1])) > 0)


def test_reactive_force_matches_offline_force():
    obstacles = [box(2, -0.5, 3, 0.5), Disc([0, 2.5], 0.4)]
    q = np.array([0.3, 0.2])
    angles, ranges = range_scan(q, obstacles, 1440, 3.0)
    segs = scan_segments(q, angles, ranges)
    assert len(segs) == 2
    f_re = reactive_repulsive_force(q, segs, 1.0, 3.0)
    f_off = sum(RepulsivePotential(o, 1.0, 3.0).force(q) for o in obstacles)
    assert np.linalg.norm(f_re - f_off) < 0.01 * np.linalg.norm(f_off)


def test_arm_joint_forces_are_minus_the_gradient_of_the_workspace_potential():
    robot = load("planar_2r")
    field = PotentialField(AttractivePotential([1.2, 0.8], 2.0), (RepulsivePotential(Disc([0.2, 1.0], 0.2), 0.5, 0.8),))
    frames = ["frame_1", "frame_2"]

    def U(q):
        P = [T[:2, 3] for T in frame_poses(robot, q, frames)]
        return float(field.attractive.potential(P[1])) + sum(float(r.potential(p)) for r in field.repulsive for p in P)

    q = np.array([0.3, 0.9])
    P = [T[:2, 3] for T in frame_poses(robot, q, frames)]
    forces = [np.sum([r.force(P[0]) for r in field.repulsive], axis=0), field.force(P[1])]
    tau = arm_joint_forces(robot, q, frames, forces)
    h = 1e-6
    fd = np.array([-(U(q + d) - U(q - d)) / (2 * h) for d in np.eye(2) * h])
    assert np.allclose(tau, fd, atol=1e-6)


def test_wavefront_equals_dijkstra_and_the_path_descends(rng):
    occ = rng.random((12, 15)) < 0.25
    occ[0, 0] = occ[-1, -1] = False
    for adj in (1, 2):
        V = wavefront(occ, (11, 14), adj)
        n_r, n_c = occ.shape
        G = lil_matrix((occ.size, occ.size))
        steps = [(0, 1), (1, 0)] + ([(1, 1), (1, -1)] if adj == 2 else [])
        for (i, j), o in np.ndenumerate(occ):
            for di, dj in steps:
                a, b = i + di, j + dj
                if 0 <= a < n_r and 0 <= b < n_c and not o and not occ[a, b]:
                    G[i * n_c + j, a * n_c + b] = np.hypot(di, dj)
        ref = dijkstra(G.tocsr(), directed=False, indices=11 * n_c + 14).reshape(occ.shape)
        ref[occ] = np.inf
        assert np.allclose(V, ref)
        if np.isfinite(V[0, 0]):
            path = steepest_descent_path(V, (0, 0), adj)
            assert np.all(np.diff(V[tuple(path.T)]) < 0) and tuple(path[-1]) == (11, 14)


def test_wavefront_rejects_bad_cells():
    occ = np.zeros((3, 3), dtype=bool)
    occ[1, 1] = True
    with pytest.raises(ValueError, match="goal"):
        wavefront(occ, (1, 1))
    with pytest.raises(ValueError, match="adjacency"):
        wavefront(occ, (0, 0), adjacency=3)
    with pytest.raises(ValueError, match="start"):
        steepest_descent_path(wavefront(occ, (0, 0)), (1, 1))


def test_reactive_force_of_a_disc_robot_uses_eta_minus_its_radius():
    q, rho = np.array([0.0, 0.0]), 0.2
    angles, ranges = range_scan(q, [Disc([1.5, 0.3], 0.4)], 1440, 3.0)
    f_re = reactive_repulsive_force(q, scan_segments(q, angles, ranges), 1.0, 1.5, robot_radius=rho)
    f_off = RepulsivePotential(Disc([1.5, 0.3], 0.4 + rho), 1.0, 1.5).force(q)   # grown obstacle, point robot
    assert np.linalg.norm(f_re - f_off) < 0.01 * np.linalg.norm(f_off)
    with pytest.raises(ValueError, match="touches"):
        reactive_repulsive_force(q, scan_segments(q, angles, ranges), 1.0, 1.5, robot_radius=1.2)
