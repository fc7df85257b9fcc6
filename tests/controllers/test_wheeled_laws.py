"""The wheeled-robot laws against their closed forms and their linearised closed loops (Sects. 11.6–11.7).

Each law's command is compared with the book's formula evaluated here at errors far from zero (where a wrong
nonlinear term shows), and the poles of its closed loop — the Jacobian of the error dynamics by central
differences, the robot moved by the law's own command — with the poles the gains were designed for.
"""

import numpy as np
import pytest

from controllers import wheeled as cw
from controllers.plants import BicycleState, MobileManipulatorPlant, Posture
from controllers.simulation import simulate
from planners.wheeled import ReferenceSample
from rigid_body.kinematics import direct_kinematics
from rigid_body.robots import load
from rigid_body.wheeled import mobile_manipulator


class Circle:
    """p_d = R(cos Ωt, sin Ωt) driven forwards: θ_d = Ωt + π/2, v_d = RΩ, ω_d = Ω (constant inputs)."""

    def __init__(self, R: float = 1.5, Omega: float = 0.4):
        self.R, self.Omega = R, Omega

    def __call__(self, t: float) -> ReferenceSample:
        R, W = self.R, self.Omega
        c, s = np.cos(W * t), np.sin(W * t)
        return ReferenceSample(np.array([R * c, R * s]), np.array([-R * W * s, R * W * c]),
                               np.array([-R * W * W * c, -R * W * W * s]), float(W * t + np.pi / 2), R * W, W)


def _posture(ref: ReferenceSample, e: np.ndarray) -> np.ndarray:
    """The posture whose tracking error (11.65) w.r.t. ``ref`` is e: θ = θ_d − e3, p = p_d − R(θ)[e1, e2]."""
    th = ref.theta - e[2]
    c, s = np.cos(th), np.sin(th)
    return np.array([ref.p[0] - (c * e[0] - s * e[1]), ref.p[1] - (s * e[0] + c * e[1]), th])


def _error_rate(law, reference, t: float, e: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """ė at error e: the unicycle at the posture of e, moved by the law's command (v, ω), and the reference,
    both by ±h (central differences)."""
    q = _posture(reference(t), e)
    v, w = law(t, Posture(*q))
    moved = [q + k * h * np.array([v * np.cos(q[2]), v * np.sin(q[2]), w]) for k in (1, -1)]
    errors = [cw.tracking_error(reference(t + k * h), *m) for k, m in zip((1, -1), moved)]
    return (errors[0] - errors[1]) / (2 * h)


def _closed_loop_poles(rate, n: int = 3, eps: float = 1e-4) -> np.ndarray:
    A = np.column_stack([(rate(eps * d) - rate(-eps * d)) / (2 * eps) for d in np.eye(n)])
    return np.sort_complex(np.linalg.eigvals(A))


def _designed(a: float, zeta: float) -> np.ndarray:
    return np.sort_complex(np.array([-2 * zeta * a, -zeta * a + 1j * a * np.sqrt(1 - zeta**2),
                                     -zeta * a - 1j * a * np.sqrt(1 - zeta**2)]))


def test_approximate_linearisation_places_the_designed_poles():
    """(11.67): k1 = k3 = 2ζa, k2 = (a² − ω_d²)/v_d give the poles −2ζa, −ζa ± ja√(1 − ζ²)."""
    ref, a, zeta = Circle(), 1.2, 0.6
    law = cw.ApproximateLinearizationTracking(ref, a, zeta)
    poles = _closed_loop_poles(lambda e: _error_rate(law, ref, 0.7, e))
    np.testing.assert_allclose(poles, _designed(a, zeta), atol=1e-5)


def test_nonlinear_tracking_linearises_to_the_same_poles_and_follows_11_70_away_from_zero():
    """k1 = k3 = 2ζ√(ω_d² + b v_d²), k2 = b: linearised, the poles of a = √(ω_d² + b v_d²); at a large heading
    error ω = ω_d + b v_d (sin e3 / e3) e2 + k3 e3 and v = v_d cos e3 + k1 e1 (11.69)–(11.70)."""
    ref, zeta, b = Circle(), 0.7, 3.0
    law = cw.NonlinearTracking(ref, zeta, b)
    r = ref(0.7)
    a = np.sqrt(r.omega**2 + b * r.v**2)
    np.testing.assert_allclose(_closed_loop_poles(lambda e: _error_rate(law, ref, 0.7, e)), _designed(a, zeta),
                               atol=1e-5)
    e = np.array([0.3, -0.4, 1.9])
    k = 2 * zeta * a
    v, w = law(0.7, Posture(*_posture(r, e)))
    np.testing.assert_allclose([v, w], [r.v * np.cos(e[2]) + k * e[0],
                                        r.omega + b * r.v * np.sin(e[2]) / e[2] * e[1] + k * e[2]], atol=1e-12)


def test_chained_form_tracking_has_the_characteristic_polynomial_of_problem_11_14():
    """Linearised about a reference with constant v1d ≠ 1, z2d: p(λ) = (λ + k1)(λ² + k2 λ + k3)."""
    k1, k2, k3, v1d, z2d = 1.5, 3.0, 2.0, 0.8, 0.3

    def reference(t):
        return np.array([v1d * t, z2d, 0.1 + z2d * v1d * t]), np.array([v1d, 0.0])

    law = cw.ChainedFormTracking(reference, k1, k2, k3)

    def rate(e, t=0.9, h=1e-5):
        z = reference(t)[0] - e
        v1, v2 = law(t, z)
        zdot = np.array([v1, v2, z[1] * v1])
        return (reference(t + h)[0] - (z + h * zdot) - (reference(t - h)[0] - (z - h * zdot))) / (2 * h)

    expected = np.sort_complex(np.r_[-k1, np.roots([1.0, k2, k3])].astype(complex))
    np.testing.assert_allclose(_closed_loop_poles(rate), expected, atol=1e-5)


def test_bicycle_steering_realises_the_outer_trackers_turn_rate_even_slowly():
    """φ_d = atan(ℓ ω v / (v² + ε)): the steering that turns at ω when v ≫ √ε, with the sign of ω v as v → 0."""
    ell, eps, k_phi = 0.8, 1e-3, 4.0
    for v, w in ((1.2, 0.4), (0.02, 0.5), (-0.02, 0.5), (0.5, -0.9)):
        law = cw.BicycleTracking(lambda t, m, v=v, w=w: np.array([v, w]), ell, phi_max=1.2, k_phi=k_phi, eps=eps)
        u = law(0.0, BicycleState(0.0, 0.0, 0.0, 0.1))
        phi_d = np.clip(np.arctan(ell * w * v / (v * v + eps)), -1.2, 1.2)
        assert np.sign(phi_d) == np.sign(w * v)
        np.testing.assert_allclose(u, [v, k_phi * (phi_d - 0.1)], atol=1e-12)


@pytest.mark.parametrize("backward", [False, True])
def test_cartesian_regulator_commands_11_78_11_79_and_s11_6(backward):
    k1, k2 = 2.0, 3.0
    law = cw.CartesianRegulator(k1, k2, backward=backward)
    for x, y, th in ((-1.0, -2.0, -np.pi / 2), (-1.0, -1.0, np.pi / 4), (0.5, -0.3, 2.0), (1.0, 2.0, -0.4)):
        n_e = -(x * np.cos(th) + y * np.sin(th))
        gamma = np.angle(np.exp(1j * (np.arctan2(y, x) - th + np.pi)))
        if backward and n_e <= 0:
            gamma -= np.sign(gamma) * np.pi
        np.testing.assert_allclose(law(0.0, Posture(x, y, th)), [k1 * n_e, k2 * gamma], atol=1e-12)


def test_posture_regulator_commands_11_82():
    k1, k2, k3 = 1.5, 2.5, 3.0
    law = cw.PostureRegulator(k1, k2, k3)
    for x, y, th in ((-1.0, -2.0, -np.pi / 2), (0.4, 0.7, 1.0), (2.0, -0.5, 3.0)):
        rho = np.hypot(x, y)
        gamma = np.angle(np.exp(1j * (np.arctan2(y, x) - th + np.pi)))
        delta = np.angle(np.exp(1j * (gamma + th)))
        expected = [k1 * rho * np.cos(gamma),
                    k2 * gamma + k1 * np.sin(gamma) * np.cos(gamma) / gamma * (gamma + k3 * delta)]
        np.testing.assert_allclose(law(0.0, Posture(x, y, th)), expected, atol=1e-12)


def test_posture_regulator_at_the_goal_point_turns_back_to_heading_zero():
    """At ρ = 0 (11.82) is undefined: the robot turns in place, ω = −k2 θ (towards θ = 0), v = 0; its log
    records γ = 0 and δ = −θ, the angle still to turn."""
    law = cw.PostureRegulator(1.0, 2.5, 3.0)
    for th in (0.5, -1.2, 3.0):
        np.testing.assert_allclose(law(0.0, Posture(0.0, 0.0, th)), [0.0, -2.5 * th], atol=1e-15)
        assert law.log()["delta"] == pytest.approx(-th) and law.log()["gamma"] == 0.0


def test_odometry_integrates_every_encoder_increment_whatever_the_distance_read():
    """(11.84) on each increment Δs since the previous call: a straight run read at 0.1 s periods gives x̂ = s, even
    when the distance read exceeds the time stamp (a fast robot)."""
    from types import SimpleNamespace

    odometry = cw.Odometry([0.0, 0.0, 0.0])
    for k in range(5):
        q_hat = odometry(0.1 * k, SimpleNamespace(distance=2.0 * k, rotation=0.0))
    np.testing.assert_allclose([q_hat.x, q_hat.y, q_hat.theta], [8.0, 0.0, 0.0], atol=1e-12)

def test_mobile_manipulator_hold_cancels_the_base_and_decays_the_error_at_rate_K():
    """While the base drives (v, ω), q̇_a = J_a†(K e − J_b u_b): the end-effector error obeys ė = −K e, so
    ‖e(t)‖ = ‖e(0)‖ e^{−K t} (damped least squares and the 1 ms hold aside)."""
    robot = mobile_manipulator(load("anthropomorphic_wrist"))
    plant = MobileManipulatorPlant(robot)
    x0 = plant.initial_state([0.0, 0.0, 0.2], [0.3, -0.6, 1.2, 0.2, 0.4, -0.3])
    import pinocchio as pin

    p0 = direct_kinematics(robot, pin.integrate(robot.model, x0, np.zeros(robot.nv)))[:3, 3]
    p_d = p0 + np.array([0.02, -0.01, 0.015])
    K = 5.0
    law = cw.MobileManipulatorHold(robot, p_d, lambda t: (0.3, 0.2), K=K)
    res = simulate(plant, law, (0.0, 1.0), x0, h=1e-3, Ts=1e-3)
    err = np.linalg.norm(res["e"], axis=1)
    rate, log0 = np.polyfit(res.t, np.log(err), 1)
    assert rate == pytest.approx(-K, rel=0.03)
    np.testing.assert_allclose(err, np.exp(log0 + rate * res.t), rtol=0.05)   # one exponential all along
    assert np.ptp(res.x[:, 0]) > 0.2                       # the base did drive
