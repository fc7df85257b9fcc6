"""ArmPlant with Coulomb friction: a sliding block and a pendulum stop where Coulomb friction predicts."""

import numpy as np
import pytest
from scipy.optimize import brentq

from controllers.plants import ArmPlant
from controllers.simulation import simulate
from rigid_body.dh import DHLink
from rigid_body.robots import load, robot_from_dh


def _free(t, meas):
    return np.zeros(meas.qd.shape)


def test_sliding_block_stops_at_the_coulomb_distance():
    """A block of mass m launched at v0 on a horizontal prismatic joint with Coulomb friction F_s decelerates
    at F_s/m: it stops after t* = m v0/F_s at x* = m v0²/(2 F_s) (no viscous friction, gravity ⟂ joint)."""
    m, v0, Fs = 2.0, 1.5, 3.0
    block = robot_from_dh([DHLink(joint="prismatic", mass=m, lower=-5.0, upper=5.0)], gravity=(0.0, -9.81, 0.0))
    plant = ArmPlant(block, coulomb_friction=Fs, friction_smoothing=1e-3)
    res = simulate(plant, _free, (0.0, 2.0), plant.initial_state([0.0], [v0]), h=1e-3)
    x, v = res.q[:, 0], res.qd[:, 0]
    assert abs(x[-1] - m * v0**2 / (2 * Fs)) < 1e-4
    assert abs(v[-1]) < 1e-6
    t_slow = res.t[np.argmax(v < 1e-2)]                                # 1 cm/s left: t* − 0.01 m/F_s
    assert abs(t_slow - m * (v0 - 1e-2) / Fs) < 2e-3
    np.testing.assert_allclose(v[res.t < 0.9], v0 - Fs / m * res.t[res.t < 0.9], atol=1e-9)  # constant deceleration


def test_pendulum_swings_down_to_the_coulomb_dead_band():
    """A point mass pendulum with Coulomb friction F_s: between two rests φ_k → φ_{k+1} the energy balance
    m g l (cos φ_{k+1} − cos φ_k) = F_s |φ_k − φ_{k+1}| holds, and it sticks at the first rest with
    m g l sin|φ| ≤ F_s (φ from the downward vertical)."""
    m, l, g, Fs = 1.0, 1.0, 9.81, 1.0
    pendulum = robot_from_dh([DHLink(a=l, mass=m)], gravity=(0.0, -g, 0.0))  # point mass at the tip
    rests = [0.8]
    while m * g * l * np.sin(abs(rests[-1])) > Fs:
        p, s = abs(rests[-1]), np.sign(rests[-1])
        rests.append(s * brentq(lambda x: m * g * l * (np.cos(x) - np.cos(p)) - Fs * (p - x), -p, p - 1e-9))
    assert len(rests) == 5 and abs(rests[-1]) < 0.1                   # four swings, then stuck
    plant = ArmPlant(pendulum, coulomb_friction=Fs)                    # the exact sgn(q̇)
    res = simulate(plant, _free, (0.0, 6.0), plant.initial_state([-np.pi / 2 + rests[0]]), h=5e-4)
    phi, w = res.q[:, 0] + np.pi / 2, res.qd[:, 0]
    turning = phi[np.flatnonzero(np.diff(np.sign(w)) != 0)]
    np.testing.assert_allclose(turning[1:4], rests[1:4], atol=1e-5)    # turning[0]: the release at rest
    assert abs(phi[-1] - rests[-1]) < 1e-3                            # held inside the dead band


def test_armplant_friction_arguments():
    puma = load("puma560")
    plant = ArmPlant(puma, friction=puma.friction, friction_smoothing=1e-2)
    x = plant.initial_state(puma.configurations["qn"], np.ones(6))
    assert np.all(np.isfinite(plant.derivative(0.0, x, np.zeros(6))))
    with pytest.raises(ValueError, match="not both"):
        ArmPlant(puma, viscous_friction=1.0, friction=puma.friction)
    with pytest.raises(ValueError, match="coulomb_friction"):
        ArmPlant(puma, coulomb_friction=-1.0)
    with pytest.raises(ValueError, match="friction_smoothing"):
        ArmPlant(puma, coulomb_friction=1.0, friction_smoothing=-1.0)
