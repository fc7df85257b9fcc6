"""Closed loops: plants, controllers and the one simulation loop (Chapters 5, 6, 8–11 of the book, MPC and MuJoCo).

Entry points (the main names are also reachable as ``rmpc.<name>``):

* ``simulation`` — ``simulate(plant, controller, (t0, t_f), x0, h, Ts)``: RK4 plant, discrete controller
  with zero-order hold → a ``SimulationResult`` (``t``, ``q``, ``qd``, ``u``, named signals, ``.plot()``);
  a diverging loop raises ``SimulationDiverged`` naming the time (and, when the controller can tell,
  which sampled-stability bound is violated). Its one RK4 step is ``rigid_body.integration``'s; ``signals`` names the columns
  of the logged signals and their units (f_x … μ_z of a wrench, x₁, y₁ … of image points) for plots.
* ``compiled`` — the same loop compiled (``simulate(..., backend="casadi")``) for laws written once against the
  primitives of ``laws`` (``ControlLaw``: one body, run by both loops).
* ``plants`` — ``ArmPlant(robot)``, the arm's rigid-body dynamics (7.82) driven by joint torques, and every other
  plant: voltage-driven arm, joint drive, servomotor, ``ArmInContact`` (Ch. 9), ``JointIntegrator`` and
  ``KinematicArm`` (q̇ = u: CLIK, resolved-velocity visual servoing), the wheeled robots (Ch. 11).
* ``environment`` — contact models for ``ArmInContact``: ``CompliantPlane``, ``SteppedPlane``, ``SurfaceWithHole``.
* ``independent_joint`` (Sect. 8.3), ``joint_space`` — ``PDGravityCompensation`` (8.51), ``InverseDynamicsControl``
  (computed torque, 8.57), ``RobustControl``, ``AdaptivePayloadControl`` (Sect. 8.5); ``operational_space``
  (Sect. 8.6; with ``force_feedback=True`` the impedance control of Sect. 9.3).
* ``force`` — Chapter 9: ``HybridForceMotionControl``, ``ForceWithInnerLoop``, ``AdmittanceControl``, the
  peg in the hole of Ch. 6 (``PegInHoleTask``, ``run_peg_in_hole``) and the design formulas.
* ``visual_servoing`` — Chapter 10: ``EyeInHandCamera``, ``PoseEstimator``, PBVS, IBVS, 2½-D laws,
  ``visual_servo(camera, law, Tc)``; ``eye_in_hand_ibvs(robot, points, T_desired)`` builds an IBVS loop in one call.
* ``wheeled`` — Chapter 11: trajectory tracking, posture regulation, odometry.
* ``potential_field`` — Chapter 12: an arm avoiding a moving obstacle by artificial potentials.
* ``tasks`` — Chapter 6: action sequencing (the pallet-filling program).
* ``scenes`` — the scenes of the book's figures and of the demos: the wall of Fig. 9.16, the Panda at a wall or
  above a target, the eye-in-hand SCARA, the planning scenes of Ch. 12, the Panda among boxes.
* ``mpc`` — beyond the book: ``ModelPredictiveControl`` (on ``planners.optimal_control``); ``mujoco`` —
  ``MujocoPlant``, the same loops on MuJoCo physics (``pip install 'rmpc[mujoco]'``).
"""
