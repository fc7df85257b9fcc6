"""Gain tuning over the compiled rollout: its gradient against finite differences, and a lower cost."""

import numpy as np

from examples.gain_tuning import cost_function, tune


def test_rollout_gradient_matches_central_differences():
    J, _ = cost_function(t_end=0.2, compile=False)
    z = np.log([3000.0, 600.0])
    grad = np.asarray(J(z)[1]).ravel()
    step = 1e-5
    fd = [(float(J(z + step * d)[0]) - float(J(z - step * d)[0])) / (2 * step) for d in np.eye(2)]
    np.testing.assert_allclose(grad, fd, rtol=1e-5)


def test_tuning_lowers_the_cost_to_a_stationary_point():
    tuned = tune(t_end=0.3)
    assert tuned.cost < 0.9 * tuned.cost0
    assert np.max(np.abs(tuned.gradient)) < 1e-3 * tuned.cost
    assert (tuned.k_P, tuned.k_D) != (tuned.k_P0, tuned.k_D0)
