"""rmpc — *Robotics: Modelling, Planning and Control* (Siciliano et al.), runnable: the main API in one place.

``import rmpc`` is instant: every name below is imported from its home module on first use
(module ``__getattr__``, PEP 562), so the command line and a notebook pay only for what they touch.

Models (``rigid_body``)
    ``load("panda", payload=2.0)``, ``robot_from_dh(links)``, ``DHLink``, ``Robot``,
    ``direct_kinematics``, ``geometric_jacobian``, ``inertia_matrix``, ``gravity_torques``,
    ``inverse_dynamics``, ``forward_dynamics``
References (``planners``)
    ``solve_ik`` (the recommended IK), ``solve_clik``, ``CLIK``, ``TaskSpace`` (which pose rows an IK or
    CLIK controls: ``TaskSpace(rows=(0, 1, 2))`` the position only), ``quintic``, ``trapezoidal``,
    ``Trajectory``, ``JointLimits``, ``minimum_time_trajectory``; optimal control (beyond the book):
    ``OptimalControlProblem``, ``StageCost``, ``OptimalControlSolver``, ``solve_optimal_control``
Closed loops (``controllers``)
    ``simulate``, ``ArmPlant``, ``PDGravityCompensation``, ``InverseDynamicsControl``,
    ``ZeroOrderHold``, ``SimulationDiverged``, ``MujocoPlant`` (the same loops on MuJoCo physics:
    ``pip install 'rmpc[mujoco]'``), ``ModelPredictiveControl``, ``MPCOptions``
Problems (``problems``)
    ``solve("8.10")``, ``all_problems()``

>>> import rmpc
>>> rmpc.load("planar_2r").nq
2
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

#: public name -> home module (one obvious home per concept; this package only points at it)
_HOMES: dict[str, str] = {
    # models and their mathematics
    "Robot": "rigid_body.robots",
    "load": "rigid_body.robots",
    "robot_from_dh": "rigid_body.robots",
    "with_payload": "rigid_body.robots",
    "DHLink": "rigid_body.dh",
    "direct_kinematics": "rigid_body.kinematics",
    "geometric_jacobian": "rigid_body.kinematics",
    "inertia_matrix": "rigid_body.dynamics",
    "gravity_torques": "rigid_body.dynamics",
    "inverse_dynamics": "rigid_body.dynamics",
    "forward_dynamics": "rigid_body.dynamics",
    # references
    "solve_ik": "planners.inverse_kinematics",
    "solve_clik": "planners.inverse_kinematics",
    "CLIK": "planners.inverse_kinematics",
    "TaskSpace": "planners.inverse_kinematics",
    "IKResult": "planners.inverse_kinematics",
    "Trajectory": "planners.timing",
    "quintic": "planners.timing",
    "trapezoidal": "planners.timing",
    "JointLimits": "planners.optimization",
    "minimum_time_trajectory": "planners.optimization",
    "OptimalControlProblem": "planners.optimal_control",
    "StageCost": "planners.optimal_control",
    "OptimalControlSolver": "planners.optimal_control",
    "OptimalControlOptions": "planners.optimal_control",
    "solve_optimal_control": "planners.optimal_control",
    # closed loops
    "simulate": "controllers.simulation",
    "SimulationResult": "controllers.simulation",
    "SimulationDiverged": "controllers.simulation",
    "ZeroOrderHold": "controllers.simulation",
    "ArmPlant": "controllers.plants",
    "MujocoPlant": "controllers.mujoco",
    "PDGravityCompensation": "controllers.joint_space",
    "InverseDynamicsControl": "controllers.joint_space",
    "ModelPredictiveControl": "controllers.mpc",
    "MPCOptions": "controllers.mpc",
    # the book's problems
    "solve": "problems.registry",
    "all_problems": "problems.registry",
}

__all__ = sorted(_HOMES)


def __getattr__(name: str) -> Any:
    home = _HOMES.get(name)
    if home is None:
        import difflib

        near = difflib.get_close_matches(name, list(_HOMES), n=3)
        raise AttributeError(f"module 'rmpc' has no attribute {name!r}" + (f"; did you mean {near}?" if near else ""))
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOMES))
