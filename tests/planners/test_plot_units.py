"""Plots say their units (from the joint types) and keep their legends clear of the curves."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from controllers.plants import ArmPlant  # noqa: E402
from controllers.simulation import simulate  # noqa: E402
from planners.timing import quintic  # noqa: E402
from rigid_body.robots import joint_units, load  # noqa: E402


def test_joint_units_follow_the_joint_types():
    assert joint_units(load("planar_pr")) == ["m", "rad"]
    assert joint_units(load("scara")) == ["rad", "rad", "m", "rad"]
    assert joint_units(load("panda")) == ["rad"] * 7


def test_trajectory_plot_labels_units_and_puts_the_legend_beside_the_axes():
    arm = load("planar_pr")
    axes = quintic([0.0, 0.0], [0.5, 1.0], 1.0, dt=0.01).plot(units=arm)
    assert [ax.get_ylabel() for ax in axes] == ["q [rad | m]", "q̇ [rad/s | m/s]", "q̈ [rad/s² | m/s²]"]
    legend = axes[0].get_legend()
    assert legend is not None
    fig = axes[0].figure
    fig.canvas.draw()
    box, area = legend.get_window_extent(), axes[0].get_window_extent()
    assert box.x0 >= area.x1 - 1  # outside the plotting area: covers no curve
    axes = quintic(0.0, 1.0, 1.0, dt=0.01).plot()
    assert axes[1].get_ylabel() == "q̇ [rad/s]" and axes[0].get_legend() is None
    plt.close("all")
    with pytest.raises(ValueError, match="units"):
        quintic(0.0, 1.0, 1.0, dt=0.01).plot(units="deg")


def test_simulation_result_units_come_from_the_arm_joint_types():
    arm = load("planar_pr")
    plant = ArmPlant(arm)
    assert plant.units["q"] == "rad | m" and plant.units["u"] == "N·m | N"
    res = simulate(plant, lambda t, m: np.zeros(2), (0.0, 0.01), plant.initial_state([0.0, 0.0]), h=1e-3)
    ax = res.plot("q")
    assert ax.get_ylabel() == "q [rad | m]"
    assert ArmPlant(load("planar_2r")).units["u"] == "N·m"
    plt.close("all")


def test_simulation_result_legend_beside_the_axes_stays_inside_the_figure():
    """Seven joints' errors: the legend goes beside the axes, and a saved PNG still shows all of it."""
    res = simulate(lambda t, x, u: -x, lambda t, m: np.zeros(1), (0.0, 0.01), np.ones(7), h=1e-3)
    ax = res.plot("x")
    fig = ax.figure
    fig.canvas.draw()
    box, area, page = ax.get_legend().get_window_extent(), ax.get_window_extent(), fig.bbox
    assert box.x0 >= area.x1 - 1 and box.x1 <= page.x1  # clear of the curves, not cut off
    plt.close("all")
