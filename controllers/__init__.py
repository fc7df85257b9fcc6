"""Closed loops: plants, controllers and the one simulation loop (Chapters 5, 6, 8–11 of the book).

Entry points:

* ``simulation.simulate(plant, controller, (t0, t_f), x0, h, Ts)`` — RK4 plant, discrete controller
  with zero-order hold → a ``SimulationResult`` (``t``, ``q``, ``qd``, ``u``, named signals, ``.plot()``);
  a diverging loop raises ``SimulationDiverged`` naming the time (and, when the controller can tell,
  which sampled-stability bound is violated).
* ``plants.ArmPlant(robot)`` — the arm's rigid-body dynamics (7.82) driven by joint torques; the
  other plants (voltage-driven arm, joint drive, contact, mobile robots) live beside it.
* ``joint_space`` — ``PDGravityCompensation`` (8.51), ``InverseDynamicsControl`` (computed torque,
  8.57), ``RobustControl``, ``AdaptivePayloadControl`` (Sect. 8.5); ``independent_joint`` (Sect. 8.3);
  ``operational_space`` (Sect. 8.6); ``force`` (Chapter 9); ``tasks`` (Chapter 6); ``wheeled`` (Chapter 11).
"""
