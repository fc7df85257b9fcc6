"""The book's controllers on MuJoCo beside the Pinocchio runs (examples/mujoco_physics.py): every check passes."""

import os

import pytest

from controllers.mujoco import INSTALL, mujoco_available

if not mujoco_available():
    if os.environ.get("CI", "").lower() == "true":
        raise ImportError(f"MuJoCo is missing under CI, where the test extra installs it: {INSTALL}")
    pytest.skip(f"MuJoCo is not installed: {INSTALL}", allow_module_level=True)

from examples.mujoco_physics import (force_control_on_mujoco, panda_wall_on_mujoco,  # noqa: E402
                                     planned_motion_on_mujoco)


@pytest.mark.parametrize("demo", [force_control_on_mujoco, panda_wall_on_mujoco, planned_motion_on_mujoco],
                         ids=lambda f: f.__name__)
def test_demo_checks_pass(demo):
    sol = demo()
    failed = [(c.name, c.detail) for c in sol.checks if not c.passed]
    assert not failed, failed
    assert sol.figures
    if demo is force_control_on_mujoco:
        v = sol.values
        assert 1e-3 < v["B_relative_difference"] < 1e-2      # the rotors' couplings, dropped by the armature model
        assert v["impedance_force_max_difference"] < 5.0 and v["joint_path_max_difference"] < 1e-2
