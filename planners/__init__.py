"""References: what the arm should do (Chapters 3, 4, 6, 11 and 12 of the book).

Entry points:

* ``inverse_kinematics.solve_ik(robot, T, q0=None)`` — the recommended IK of one pose (global, with
  restarts); ``solve_clik`` (local, from a nearby guess), ``CLIK`` (tracking a moving reference,
  Sect. 3.7), ``CasadiIK``, ``QPVelocityIK``; every solver returns an ``IKResult``.
* ``timing`` — timing laws → a ``Trajectory`` (``t, q, qd, qdd``, ``.plot()``): ``quintic``, ``cubic``,
  ``trapezoidal``, ``cubic_spline``, ``linear_parabolic_blends`` … (Sect. 4.2).
* ``optimization`` — ``minimum_time_trajectory(robot, q_i, q_f, JointLimits(...))`` under torque
  limits, ``minimum_effort_trajectory``, ``minimum_jerk_trajectory`` → an ``OptimalTrajectory``.
* ``paths`` (segments, circles, orientation, Sect. 4.3), ``tasks`` (Chapter 6), ``configuration_space``,
  ``sampling`` (PRM, RRT), ``potentials``, ``cells`` (Chapter 12), ``wheeled`` (Chapter 11).
"""
