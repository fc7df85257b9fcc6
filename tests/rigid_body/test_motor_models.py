"""The two motor models side by side: the book's rotors (mimic joints) and the Toolbox's armature J_m G²."""

import dataclasses

import numpy as np

from rigid_body import dynamics as dyn
from rigid_body.dh import DHLink
from rigid_body.robots import robot_from_dh

LINKS = [
    DHLink(alpha=np.pi / 2, d=0.3, mass=4.0, com=(0, -0.1, 0), inertia=np.diag([0.1, 0.05, 0.1]),
           motor_inertia=2e-4, gear_ratio=-60.0),
    DHLink(a=0.5, mass=3.0, com=(-0.25, 0, 0.02), inertia=np.diag([0.01, 0.08, 0.08]), motor_inertia=3e-4,
           gear_ratio=100.0),
    DHLink(alpha=-np.pi / 2, joint="prismatic", mass=1.5, com=(0, 0, -0.1), inertia=np.diag([0.02, 0.02, 0.01]),
           motor_inertia=1e-4, gear_ratio=400.0, lower=0.0, upper=0.5),
    DHLink(a=0.1, mass=0.5, inertia=np.eye(3) * 1e-3, motor_inertia=5e-5, gear_ratio=50.0),
]


def test_armature_inertia_is_links_plus_diagonal_exactly(rng):
    """B(q) = B_links(q) + diag(k_r² I_m): no coupling terms, whatever q; g(q) is the links'."""
    armature = robot_from_dh(LINKS, motors="armature")
    bare = robot_from_dh([dataclasses.replace(l, motor_inertia=0.0) for l in LINKS])
    diag = np.array([l.gear_ratio ** 2 * l.motor_inertia for l in LINKS])
    rotors = robot_from_dh(LINKS)
    for _ in range(5):
        q = rng.uniform(-1.0, 1.0, size=4)
        q[2] = abs(q[2]) / 2
        np.testing.assert_allclose(dyn.inertia_matrix(armature, q), dyn.inertia_matrix(bare, q) + np.diag(diag),
                                   rtol=0, atol=1e-12)
        np.testing.assert_allclose(dyn.gravity_torques(armature, q), dyn.gravity_torques(bare, q), atol=1e-12)
        # the book's rotors add the couplings k_r I_m z_{i−1}ᵀ ω_{i−1} and I_m (z_{i−1}ᵀ ω_{i−1})²: of order
        # |k_r| I_m, not k_r² I_m — and not zero
        coupling = dyn.inertia_matrix(rotors, q) - dyn.inertia_matrix(armature, q)
        bound = max(abs(l.gear_ratio) * l.motor_inertia + l.motor_inertia for l in LINKS)
        assert 1e-6 < np.abs(coupling).max() <= bound


def test_armature_forward_dynamics_by_aba_solves_the_model(rng):
    """ABA (no mimic joints) against the Cholesky solve of B q̈ = τ − h and the rotor model's route."""
    armature = robot_from_dh(LINKS, motors="armature")
    assert not armature.has_mimic and robot_from_dh(LINKS).has_mimic
    for _ in range(3):
        q, qd, tau = rng.uniform(-1, 1, size=4), rng.normal(size=4), rng.normal(size=4)
        B, h = dyn.inertia_matrix(armature, q), dyn.nonlinear_effects(armature, q, qd)
        np.testing.assert_allclose(dyn.forward_dynamics(armature, q, qd, tau), np.linalg.solve(B, tau - h), atol=1e-10)


def test_armature_keeps_the_rotor_mass_on_the_previous_link(rng):
    """A motor mass rides on link i−1 at the origin of frame i−1 in both models: same gravity torques."""
    heavy = [dataclasses.replace(l, motor_mass=2.0) for l in LINKS]
    armature, rotors = robot_from_dh(heavy, motors="armature"), robot_from_dh(heavy)
    q = rng.uniform(-1, 1, size=4)
    np.testing.assert_allclose(dyn.gravity_torques(armature, q), dyn.gravity_torques(rotors, q), atol=1e-10)
    assert np.abs(dyn.gravity_torques(armature, q) - dyn.gravity_torques(robot_from_dh(LINKS), q)).max() > 1.0
