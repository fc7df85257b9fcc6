"""References: what the arm should do (Chapters 3, 4, 6, 11 and 12 of the book, and optimal control beyond it).

Entry points (every name below is also reachable as ``rmpc.<name>``):

* ``inverse_kinematics`` — ``solve_ik(robot, T, q0=None)``, the recommended IK of one pose (global, with
  restarts); ``solve_clik`` (local, from a nearby guess), ``CLIK`` (tracking a moving reference,
  Sect. 3.7), ``CasadiIK``, ``QPVelocityIK``; every solver returns an ``IKResult``.
* ``timing`` — timing laws → a ``Trajectory`` (``t, q, qd, qdd``, ``.plot()``): ``quintic``, ``cubic``,
  ``trapezoidal``, ``cubic_spline``, ``linear_parabolic_blends`` … (Sect. 4.2).
* ``paths`` — operational-space paths: segments, circles, orientation (Sect. 4.3).
* ``optimization`` — ``minimum_time_trajectory(robot, q_i, q_f, JointLimits(...))`` under torque
  limits, ``minimum_effort_trajectory``, ``minimum_jerk_trajectory`` → an ``OptimalTrajectory``.
* ``optimal_control`` — beyond the book: ``OptimalControlProblem`` solved by multiple shooting
  (``solve_optimal_control``), the optimiser behind ``controllers.mpc``; ``stage_qp`` holds its step QP's
  solvers (HPIPM through its C interface, checked before first use, and a sparse fallback).
* ``tasks`` — Chapter 6: a task decomposed into actions and their paths (pick-and-place).
* ``wheeled`` — Chapter 11: flat outputs, Cartesian polynomial paths, ``FigureEight``, chained forms,
  Dubins and Reeds–Shepp paths, ``uniform_time_scaling``.
* Chapter 12, motion planning:

  * ``configuration_space`` — planar scenes (``Disc``, ``Polygon``), ``PlanarCSpace`` of a planar arm or body,
    distances, C-obstacles, certified straight motions;
  * ``collision`` — URDF arms among boxes: ``Box``, ``CollisionChecker`` (coal distances, self-collision pairs),
    ``UrdfCSpace`` (the planners' space, certified edges);
  * ``sampling`` — ``prm``, ``rrt``, ``rrt_connect``, ``unicycle_rrt``, ``shortcut`` → ``PlanResult``
    (``certified``: collision-free along every edge, not only at samples; ``min_clearance`` [m]);
    ``edge_check="sampled"`` checks sampled configurations only, faster, and says ``certified=False``;
  * ``potentials`` — artificial potentials, ``gradient_descent``, navigation functions on grids (``wavefront``);
  * ``cells`` — trapezoidal and quadtree decompositions, visibility graph, Voronoi (GVD);
  * ``time_optimal`` — ``time_optimal_path(robot, path, limits, space=)`` times a planned polyline (TOPP-RA) with
    blends certified as the path is → ``TimeOptimalPath`` (callable in t).
"""
