"""Extra assertions on chapter 2's problems: the 2.15 value keys of ARCHITECTURE.md and the 2.17 checks' teeth."""

from __future__ import annotations

import json

import numpy as np
import pytest
from matplotlib.path import Path as PolygonPath

from problems.cli import solution_dict
from problems.registry import solve
from rigid_body.kinematics import planar_3r_workspace_contour, workspace_points
from rigid_body.robots import load


def test_2_15_json_carries_the_architecture_keys():
    sol = solve("2.15")
    d = json.loads(json.dumps(solution_dict(sol)))
    for key in ("R1", "R2", "R1R2", "R2R1"):
        assert np.shape(d["values"][key]) == (3, 3)
    for key in ("euler_R1R2", "euler_R2R1"):
        assert np.shape(d["values"][key]) == (2, 3)  # two ZYZ sets, (2.19) then (2.20)
    assert all(c["passed"] for c in d["checks"])


def test_2_17_contour_check_can_fail():
    """A contour that misses part of the workspace leaves samples outside (the check is not vacuous)."""
    rng = np.random.default_rng(0)
    robot = load("planar_3r")
    poly = planar_3r_workspace_contour(robot).points
    samples = workspace_points(robot, 5000, rng)[:, :2]
    assert PolygonPath(poly).contains_points(samples).mean() > 0.999
    shrunk = 0.9 * poly
    assert PolygonPath(shrunk).contains_points(samples).mean() < 0.95


def test_2_17_contour_requires_symmetric_limits():
    robot = load("planar_3r", lower=(-1.0, -1.0, -0.5), upper=(1.0, 2.0, 0.5))
    with pytest.raises(ValueError, match="symmetric"):
        planar_3r_workspace_contour(robot)
