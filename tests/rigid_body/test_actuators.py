"""DC servomotor and hydraulic drive: transfer functions (block reduction) against the ODE plant and closed forms."""

import control
import numpy as np
import pytest

from controllers.plants import ServomotorPlant
from controllers.simulation import simulate
from rigid_body.actuators import (DCServomotor, HydraulicMotor, PIRegulator, design_pi_current_loop,
                                  frequency_samples, hydraulic_transfer_functions, servomotor_transfer_functions)

MOTOR = dict(Ra=0.2, La=2e-3, kt=0.2, kv=0.2, Im=0.0014, Fm=0.01, Gv=1.0, Tv=1e-4)


def test_plant_step_matches_transfer_function_with_load_torque():
    m = DCServomotor(**MOTOR)
    res = simulate(ServomotorPlant(m), lambda t, x: np.array([1.0, 0.05]), (0.0, 0.1), ServomotorPlant.x0, h=1e-4)
    tf = servomotor_transfer_functions(m)
    ref = (control.step_response(tf.velocity_input, res.t).outputs
           + 0.05 * control.step_response(tf.velocity_load, res.t).outputs)
    assert np.max(np.abs(ref - res.x[:, 1])) < 1e-3


def test_steady_state_equals_dc_gain(rng):
    for _ in range(5):
        m = DCServomotor(Ra=rng.uniform(0.1, 1), La=1e-3, kt=rng.uniform(0.1, 1), kv=rng.uniform(0.1, 1),
                         Im=1e-3, Fm=rng.uniform(1e-3, 0.1), ki=rng.uniform(0, 2))
        K = rng.uniform(0.5, 5)
        omega, i_a = m.steady_state(1.0, 0.0, K)
        tf = servomotor_transfer_functions(m, K)
        assert omega == pytest.approx(control.dcgain(tf.velocity_input), rel=1e-9)
        assert i_a == pytest.approx(control.dcgain(tf.current_input), rel=1e-9)


def test_pi_current_design_places_poles():
    m = DCServomotor(**{**MOTOR, "Tv": 0.0, "kv": 1e-12}, ki=1.0)
    pi, wn = design_pi_current_loop(m, 0.7, 2e-3)
    poles = control.poles(servomotor_transfer_functions(m, pi).current_input)
    fast = poles[np.abs(poles) > 100]                 # the electrical pair (the rotor pole is ~ −F_m/I_m)
    assert np.allclose(np.abs(fast), wn, rtol=1e-6)
    assert np.allclose(-fast.real / np.abs(fast), 0.7, rtol=1e-6)


def test_design_rejects_bad_specifications():
    with pytest.raises(ValueError, match="ki > 0"):
        design_pi_current_loop(DCServomotor(**MOTOR), 0.7, 2e-3)
    with pytest.raises(ValueError, match="too slow"):
        design_pi_current_loop(DCServomotor(**MOTOR, ki=1.0), 0.7, 1.0)
    with pytest.raises(ValueError, match="`Ra`"):
        DCServomotor(**{**MOTOR, "Ra": -1.0})
    with pytest.raises(ValueError, match="`K`"):
        PIRegulator(0.0, 1.0)


def test_hydraulic_velocity_gain_at_low_frequency(rng):
    p = HydraulicMotor(*rng.uniform(0.5, 2.0, 10))
    G_v, _ = hydraulic_transfer_functions(p)
    w = np.array([1e-6])
    static = p.kx * p.Gs / (p.kr * p.kq) / (1 + p.Fm * (1 + p.kr * p.kl) / (p.kt * p.kr * p.kq))
    assert (1j * w * frequency_samples(G_v, w))[0].real == pytest.approx(static, rel=1e-5)


def test_non_finite_operating_points_and_regulators_raise():
    m = DCServomotor(**MOTOR)
    with pytest.raises(ValueError, match="`v_c`"):
        m.steady_state(float("nan"))
    with pytest.raises(ValueError, match="`K`"):
        m.steady_state(1.0, 0.0, K=0.0)
    with pytest.raises(ValueError, match="`regulator`"):
        ServomotorPlant(m, float("nan"))
    with pytest.raises(ValueError, match="`regulator`"):
        servomotor_transfer_functions(m, -1.0)
