"""Independent joint control: designs meet their specifications; feedforward tracks; inertia bounds."""

import control
import numpy as np
import pytest

from controllers.independent_joint import (JointDrive, PositionVelocityController, Transducers,
                                           bandwidth, design_position_feedback, design_position_velocity,
                                           feedforward_reference,
                                           design_position_velocity_acceleration, inertia_bounds, position_feedback,
                                           position_velocity_acceleration_feedback, position_velocity_feedback)
from controllers.plants import JointDrivePlant
from controllers.simulation import simulate

DRIVE = JointDrive(I=6.0, Ra=0.3, kt=0.5, kv=0.5, Fm=0.001)


def _damping(W):
    wn, zeta, _ = control.damp(W, doprint=False)
    return wn, zeta


def test_position_velocity_designs_meet_specifications(rng):
    for _ in range(5):
        zeta, wn = rng.uniform(0.3, 0.9), rng.uniform(5, 50)
        t = Transducers(*rng.uniform(0.5, 2, 3))
        d5 = design_position_velocity(DRIVE, zeta, wn, t)
        d6 = design_position_velocity_acceleration(DRIVE, zeta, wn, 2 * wn**2 / DRIVE.k_m, t)
        for d in (d5, d6):
            w, z = _damping(d.closed_loop.reference)
            assert np.allclose(w, wn) and np.allclose(z, zeta)
            assert control.dcgain(d.closed_loop.reference) == pytest.approx(1 / t.k_TP)
        assert d6.K_P * t.k_TP * d6.K_V * d6.K_A == pytest.approx(2 * wn**2 / DRIVE.k_m)


def test_position_feedback_design_damping():
    d = design_position_feedback(DRIVE, 0.5, 10 * DRIVE.T_m)
    complex_poles = d.poles[np.abs(d.poles.imag) > 0]
    assert np.allclose(-complex_poles.real / np.abs(complex_poles), 0.5)
    with pytest.raises(ValueError, match="`zeta`"):
        design_position_feedback(DRIVE, 1.2, 72.0)


def test_acceleration_design_needs_enough_rejection():
    with pytest.raises(ValueError, match="`X_R` must exceed"):
        design_position_velocity_acceleration(DRIVE, 0.4, 20.0, 100.0)


def test_bandwidth_of_second_order():
    W = control.tf([1.0], [1 / 400.0, np.sqrt(2.0) / 20.0, 1.0])
    assert bandwidth(W) == pytest.approx(20.0, rel=1e-3)        # ζ = 1/√2: ω_3 = ω_n


def test_feedforward_tracks_sampled_trajectory():
    d = design_position_velocity(DRIVE, 0.4, 20.0)

    def ref(t):
        return np.sin(t), np.cos(t), -np.sin(t)

    err = {}
    for ff in (True, False):
        res = simulate(JointDrivePlant(DRIVE), PositionVelocityController(d, DRIVE, ref, Ts=1e-3, feedforward=ff),
                       (0.0, 2.0), [0.0, 1.0], h=5e-4, Ts=1e-3)
        err[ff] = np.max(np.abs(res["e"]))
    assert err[True] < 1e-3 and err[True] < err[False] / 20     # what is left is the ZOH delay ~ Ts/2 · ϑ̇


def test_inertia_bounds_alpha_bound(rng):
    Bs = []
    for _ in range(20):
        A = rng.normal(size=(3, 3))
        Bs.append(A @ A.T + np.eye(3))
    b = inertia_bounds(Bs)
    for B in Bs:
        assert np.linalg.norm(np.linalg.solve(B, b.B_hat) - np.eye(3), 2) <= b.alpha + 1e-12
    with pytest.raises(ValueError, match="positive definite"):
        inertia_bounds([-np.eye(2)])


def test_bad_gains_transducers_and_systems_raise():
    with pytest.raises(ValueError, match="`K_P`"):
        position_feedback(DRIVE, float("nan"), 72.0)
    with pytest.raises(ValueError, match="`K_V`"):
        position_velocity_feedback(DRIVE, 25.0, -8.0, DRIVE.T_m)
    with pytest.raises(ValueError, match="`T_A`"):
        position_velocity_acceleration_feedback(DRIVE, 25.0, 32.0, 0.5, -1.0)
    with pytest.raises(ValueError, match="`k_TP`"):
        Transducers(-1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="bandwidth"):
        bandwidth(control.tf([1.0], [1.0, -1.0]))
    with pytest.raises(ValueError, match="finite"):
        inertia_bounds(np.full((1, 2, 2), np.nan))


def test_feedforward_references_equal_the_closed_forms_of_problem_8_7():
    """Θ'_r/Θ_d of Figs. 8.12–8.14 against the manual's polynomials, at several frequencies, for a
    drive with non-unit transducers (a dropped k_TV, k_TA or K_A term shows here)."""
    drive = JointDrive(I=6.0, Ra=0.3, kt=0.5, kv=0.5)
    t = Transducers(1.3, 0.7, 0.4)
    km, Tm = drive.k_m, drive.T_m
    s = 1j * np.array([0.1, 1.0, 7.0, 40.0])
    P = design_position_feedback(drive, 0.4, 10 * Tm)
    V = design_position_velocity(drive, 0.4, 20.0)
    A = design_position_velocity_acceleration(drive, 0.4, 20.0, 400.0)
    cases = [
        (P, t.k_TP + s**2 * (1 + s * Tm) / (km * P.K_P * (1 + s * P.T_P))),
        (V, t.k_TP + s * t.k_TV / V.K_P + s**2 / (km * V.K_P * V.K_V)),
        (A, t.k_TP + s * t.k_TV / A.K_P + (1 + km * A.K_A * t.k_TA) * s**2 / (km * A.K_P * A.K_V * A.K_A)),
    ]
    for design, manual in cases:
        G = feedforward_reference(drive, design, t)
        assert np.allclose(G(s), manual, rtol=1e-10)
