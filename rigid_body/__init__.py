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
  ``operational_space``, ``regressor``, ``actuators``, ``sensors``, ``camera``, ``vision`` (homographies, poses
  from images), ``wheeled``.
* The book's robots as data: ``book_robots`` (DH tables, masses, motors; writes ``urdf/``), ``dh`` (a DH table
  → URDF → Pinocchio), ``trees`` (the humanoid, branches), ``closed_chain`` (the four-link closed chain of 2.11).
* Independent references the tests check Pinocchio against: ``lagrange`` (the Lagrange formulation),
  ``newton_euler`` (the book's RNEA in DH frames).
* Shared machinery: ``symbolic`` (CasADi expressions of a ``pin.Model``: kinematics, RNEA, CRBA, forward
  dynamics), ``integration`` (the one RK4 step of the simulation loops and of optimal control), ``codegen``
  (CasADi functions compiled to C and cached in ``$RMPC_CACHE``), ``validation`` (every input check and its
  message).

The short path to all of these is the :mod:`rmpc` package (``rmpc.load``, ``rmpc.direct_kinematics`` …).
"""
