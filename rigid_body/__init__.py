"""Models and their mathematics (Chapters 2, 3, 5, 7 and 11 of the book).

Entry points:

* ``robots.load(name, payload=None)`` — a :class:`robots.Robot` (``pin.Model`` + data + end effector)
  for the book's arms (``"planar_2r"``, ``"scara"``, ``"anthropomorphic_wrist"`` …, ``robots.available()``)
  and real robots (``"panda"``, ``"ur5"``); ``robots.robot_from_dh([dh.DHLink(...), ...])`` for any DH table.
* ``kinematics`` — ``direct_kinematics``, ``geometric_jacobian``, ``analytical_jacobian``, closed-form IK
  of the book's arms (``inverse_kinematics_*``), workspace.
* ``dynamics`` — ``inertia_matrix`` B(q), ``coriolis_matrix``, ``gravity_torques`` g(q),
  ``inverse_dynamics`` (RNEA), ``forward_dynamics``, ``friction_torques``.
* ``rotations``, ``se3`` — rotation matrices, Euler/RPY, axis–angle, quaternions, twists.
* ``task_space`` — pose errors and generalised inverses; ``statics``, ``manipulability``,
  ``operational_space``, ``regressor``, ``actuators``, ``sensors``, ``camera``, ``wheeled``.

The short path to all of these is the :mod:`rmpc` package (``rmpc.load``, ``rmpc.direct_kinematics`` …).
"""
