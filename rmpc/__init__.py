"""rmpc — *Robotics: Modelling, Planning and Control* (Siciliano et al.), runnable: the main API in one place.

``import rmpc`` is instant: every name below is imported from its home module on first use
(module ``__getattr__``, PEP 562), so the command line and a notebook pay only for what they touch.
Each name is the object of its home module (named in brackets): ``help(rmpc.X)`` tells where it lives.

Models (Ch. 2, 3, 7) [``rigid_body``]
    ``load("panda", payload=2.0)``, ``robot_from_dh(links)``, ``DHLink``, ``Robot``, ``with_payload``,
    ``direct_kinematics``, ``geometric_jacobian``, ``inertia_matrix``, ``gravity_torques``,
    ``inverse_dynamics``, ``forward_dynamics``
Kinematic references (Ch. 3, 4) [``planners``]
    ``solve_ik`` (the recommended IK), ``solve_clik``, ``CLIK``, ``TaskSpace`` (which pose rows an IK or
    CLIK controls: ``TaskSpace(rows=(0, 1, 2))`` the position only), ``IKResult``, ``quintic``, ``trapezoidal``,
    ``Trajectory``, ``JointLimits``, ``minimum_time_trajectory``
Motion control (Ch. 8) [``controllers``]
    ``simulate``, ``SimulationResult``, ``SimulationDiverged``, ``ZeroOrderHold``, ``ArmPlant``,
    ``PDGravityCompensation`` (8.51), ``InverseDynamicsControl`` (8.57), ``OperationalPDGravity`` (8.110),
    ``OperationalInverseDynamics`` (8.114; with ``force_feedback=True`` the impedance control of Ch. 9)
A law of your own [``controllers.laws``, ``controllers.compiled``]
    subclass ``ControlLaw`` and write its body ``law(ops, K, q, qd, ref)`` once: ``simulate`` runs it
    numerically, ``simulate(..., backend="casadi")`` compiles the same body; a block that has no symbolic form is
    refused there with ``NoSymbolicForm`` naming it (it runs on the default Python loop; README, tour step 12)
Force control (Ch. 9) [``controllers.force``, ``controllers.environment``, ``controllers.plants``]
    the plant ``ArmInContact(robot, environment, frame=)`` (measures the wrench h_e), the environments
    ``CompliantPlane``, ``SteppedPlane``, ``SurfaceWithHole``; the laws ``HybridForceMotionControl`` (9.77)–(9.81),
    ``ForceWithInnerLoop`` (Sect. 9.4), ``AdmittanceControl`` (Fig. 9.7); ``selection_matrices`` (S_f, S_v of a
    task frame), ``impedance_parameters``, ``force_loop_parameters``, ``compliance_equilibrium``;
    the peg in the hole of Ch. 6: ``PegInHoleTask``, ``run_peg_in_hole``
Visual servoing (Ch. 10) [``rigid_body.camera``, ``rigid_body.vision``, ``controllers.visual_servoing``]
    cameras ``PinholeCamera``, ``FieldOfView``, ``view_target``; the blocks ``EyeInHandCamera``,
    ``TargetFeatures``, ``PoseEstimator``, ``visual_servo(camera, law, Tc)``; the laws ``PBVSPDGravity``,
    ``PBVSResolvedVelocity``, ``PBVSPoseResolvedVelocity``, ``IBVSPDGravity``, ``IBVSResolvedVelocity``,
    ``HybridVisualServo``; the kinematic plant of resolved-velocity loops ``KinematicArm`` (q̇ = u);
    ``eye_in_hand_ibvs(robot, points, T_desired, frame=)`` builds camera, desired features and loop in one call;
    ``homography_dlt``, ``pose_from_homography``
Mobile robots (Ch. 11) [``controllers.plants``, ``controllers.wheeled``, ``planners.wheeled``]
    plants ``UnicyclePlant``, ``BicyclePlant``, ``ChainedFormPlant``; paths ``FigureEight``,
    ``cartesian_polynomial_path``, ``uniform_time_scaling``, ``dubins_path``, ``reeds_shepp_path``;
    controllers ``NonlinearTracking`` (11.68)–(11.70), ``ApproximateLinearizationTracking``, ``InputOutputTracking``,
    ``CartesianRegulator`` (11.78), ``PostureRegulator`` (11.80)–(11.82), ``Odometry``
Motion planning (Ch. 12) [``planners.sampling``, ``planners.collision``, ``planners.configuration_space``, …]
    URDF arms among boxes ``Box``, ``CollisionChecker``, ``UrdfCSpace``; planar scenes ``PlanarCSpace``,
    ``Disc``, ``Polygon``; planners ``prm``, ``rrt``, ``rrt_connect``, ``unicycle_rrt``, ``shortcut`` →
    ``PlanResult`` (``certified``: collision-free along every edge); ``PotentialField``, ``gradient_descent``,
    ``wavefront``, ``trapezoidal_decomposition``, ``visibility_graph``; timing a planned path:
    ``time_optimal_path(robot, path, limits, space=)`` → ``TimeOptimalPath`` (certified like the path)
Beyond the book [``planners.optimal_control``, ``controllers.mpc``, ``controllers.mujoco``]
    optimal control ``OptimalControlProblem``, ``StageCost``, ``OptimalControlSolver``, ``OptimalControlOptions``,
    ``solve_optimal_control``; ``ModelPredictiveControl``, ``MPCOptions``; ``MujocoPlant`` (the same loops on
    MuJoCo physics: ``pip install 'rmpc[mujoco]'``)
Scenes and pictures [``controllers.scenes``, ``viewer``]
    ``rmpc.scenes`` (the book's scenes and the demos': the plane of Fig. 9.16, the Panda at a wall or above a
    target, the eye-in-hand SCARA, the planning scenes of Ch. 12, the Panda among boxes), ``rmpc.viewer``
    (``show``, ``animate``, ``export_html``: a 3-D page with no server and no network)
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

#: public name -> home module (one obvious home per concept; this package only points at it), by chapter
_HOMES: dict[str, str] = {
    # models and their mathematics (Ch. 2, 3, 7)
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
    # kinematic references (Ch. 3, 4)
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
    # motion control (Ch. 8)
    "simulate": "controllers.simulation",
    "SimulationResult": "controllers.simulation",
    "SimulationDiverged": "controllers.simulation",
    "ZeroOrderHold": "controllers.simulation",
    "ArmPlant": "controllers.plants",
    "PDGravityCompensation": "controllers.joint_space",
    "InverseDynamicsControl": "controllers.joint_space",
    "OperationalPDGravity": "controllers.operational_space",
    "OperationalInverseDynamics": "controllers.operational_space",
    # a law written once, run by both loops
    "ControlLaw": "controllers.laws",
    "NoSymbolicForm": "controllers.compiled",
    # force control (Ch. 9)
    "ArmInContact": "controllers.plants",
    "CompliantPlane": "controllers.environment",
    "SteppedPlane": "controllers.environment",
    "SurfaceWithHole": "controllers.environment",
    "HybridForceMotionControl": "controllers.force",
    "ForceWithInnerLoop": "controllers.force",
    "AdmittanceControl": "controllers.force",
    "impedance_parameters": "controllers.force",
    "force_loop_parameters": "controllers.force",
    "compliance_equilibrium": "controllers.force",
    "PegInHoleTask": "controllers.force",
    "run_peg_in_hole": "controllers.force",
    "selection_matrices": "rigid_body.task_space",
    # visual servoing (Ch. 10)
    "PinholeCamera": "rigid_body.camera",
    "FieldOfView": "rigid_body.camera",
    "view_target": "rigid_body.camera",
    "homography_dlt": "rigid_body.vision",
    "pose_from_homography": "rigid_body.vision",
    "EyeInHandCamera": "controllers.visual_servoing",
    "TargetFeatures": "controllers.visual_servoing",
    "PoseEstimator": "controllers.visual_servoing",
    "PBVSPDGravity": "controllers.visual_servoing",
    "PBVSResolvedVelocity": "controllers.visual_servoing",
    "PBVSPoseResolvedVelocity": "controllers.visual_servoing",
    "IBVSPDGravity": "controllers.visual_servoing",
    "IBVSResolvedVelocity": "controllers.visual_servoing",
    "HybridVisualServo": "controllers.visual_servoing",
    "visual_servo": "controllers.visual_servoing",
    "eye_in_hand_ibvs": "controllers.visual_servoing",
    "KinematicArm": "controllers.plants",
    # mobile robots (Ch. 11)
    "UnicyclePlant": "controllers.plants",
    "BicyclePlant": "controllers.plants",
    "ChainedFormPlant": "controllers.plants",
    "FigureEight": "planners.wheeled",
    "cartesian_polynomial_path": "planners.wheeled",
    "uniform_time_scaling": "planners.wheeled",
    "dubins_path": "planners.wheeled",
    "reeds_shepp_path": "planners.wheeled",
    "NonlinearTracking": "controllers.wheeled",
    "ApproximateLinearizationTracking": "controllers.wheeled",
    "InputOutputTracking": "controllers.wheeled",
    "CartesianRegulator": "controllers.wheeled",
    "PostureRegulator": "controllers.wheeled",
    "Odometry": "controllers.wheeled",
    # motion planning (Ch. 12)
    "Box": "planners.collision",
    "CollisionChecker": "planners.collision",
    "UrdfCSpace": "planners.collision",
    "PlanarCSpace": "planners.configuration_space",
    "Disc": "planners.configuration_space",
    "Polygon": "planners.configuration_space",
    "prm": "planners.sampling",
    "rrt": "planners.sampling",
    "rrt_connect": "planners.sampling",
    "unicycle_rrt": "planners.sampling",
    "shortcut": "planners.sampling",
    "PlanResult": "planners.sampling",
    "PotentialField": "planners.potentials",
    "gradient_descent": "planners.potentials",
    "wavefront": "planners.potentials",
    "trapezoidal_decomposition": "planners.cells",
    "visibility_graph": "planners.cells",
    "time_optimal_path": "planners.time_optimal",
    "TimeOptimalPath": "planners.time_optimal",
    # beyond the book: optimal control, MPC, MuJoCo
    "OptimalControlProblem": "planners.optimal_control",
    "StageCost": "planners.optimal_control",
    "OptimalControlSolver": "planners.optimal_control",
    "OptimalControlOptions": "planners.optimal_control",
    "solve_optimal_control": "planners.optimal_control",
    "ModelPredictiveControl": "controllers.mpc",
    "MPCOptions": "controllers.mpc",
    "MujocoPlant": "controllers.mujoco",
    # the book's problems
    "solve": "problems.registry",
    "all_problems": "problems.registry",
}

#: modules reachable as attributes: ``rmpc.viewer.show(...)``, ``rmpc.scenes.panda_wall()``
_MODULES: dict[str, str] = {"viewer": "viewer", "scenes": "controllers.scenes"}

__all__ = sorted(_HOMES) + sorted(_MODULES)


def __getattr__(name: str) -> Any:
    if name in _MODULES:
        value = importlib.import_module(_MODULES[name])
    else:
        home = _HOMES.get(name)
        if home is None:
            import difflib

            near = difflib.get_close_matches(name, [*_HOMES, *_MODULES], n=3)
            raise AttributeError(f"module 'rmpc' has no attribute {name!r}" + (f"; did you mean {near}?" if near else ""))
        value = getattr(importlib.import_module(home), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_HOMES) | set(_MODULES))
