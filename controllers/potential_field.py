"""Potential-field control of an arm among a moving obstacle: Sect. 12.6.4 closed in the loop.

The artificial potential of Sect. 12.6 acts on the manipulator as generalised forces (Sect. 12.6.4):
the attractive force on the end effector and the repulsive force on the point of the arm closest to
the obstacle, mapped to joint torques through the transposed Jacobians of those points (Eq. (3.111),
τ = Jᵀγ). Used as a *torque* law rather than as a velocity reference, with gravity compensation and
joint damping it is the PD + gravity scheme (8.51) with the quadratic joint potential replaced by the
workspace potential:

    τ = g(q) + J_Pᵀ(q) f_a + J_cᵀ(q) f_r − K_D q̇,
    f_a = k_a (p_g − p_e)                     (paraboloid, Sect. 12.6.1),
    f_r = (k_r/η²)(1/η − 1/η₀)^{γ−1} ∇η       (Eq. (12.15), at the closest point c of the arm),

with η the distance of the arm from a disc obstacle whose centre moves, ``center(t)``. J_cᵀ f_r is
‖f_r‖ ∂η/∂q (the gradient of the arm–disc distance of Problem 3.21, in
:mod:`planners.configuration_space`). Planar arms (the book's ``planar_2r``/``planar_3r``), motion in
the x–y plane.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 12.6.1–12.6.4 (potentials, Eq. (12.15), manipulators), Eq. (8.51) (PD + gravity compensation).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import pinocchio as pin

from controllers.plants import ArmMeasurement
from controllers.simulation import LoggedController
from planners.configuration_space import planar_arm_obstacle_distance, planar_arm_obstacle_distance_gradient
from planners.potentials import repulsive_magnitude
from rigid_body.robots import Robot
from rigid_body.validation import as_positive, as_vector

__all__ = ["PotentialFieldControl"]


class PotentialFieldControl(LoggedController):
    """τ = g(q) + J_Pᵀ f_a + ‖f_r‖ ∂η/∂q − K_D q̇ for a planar arm and a moving disc (module docstring).

    Parameters
    ----------
    robot : the planar arm (links = segments between the origins of ``frame_0 … frame_n``).
    goal : end-effector goal position p_g (2,) [m] in the x–y plane.
    center : ``t -> (2,)`` position of the obstacle's centre [m] at time t (measured by the controller).
    radius : obstacle radius [m].
    k_a : attractive gain [N/m]; k_r : repulsive gain [N·m²]; eta0 : range of influence η₀ [m].
    K_D : joint damping, scalar or (n,) [N·m·s/rad].

    Logs ``eta`` (the clearance measured by the controller), ``p_e`` and ``tau_r`` (the repulsive
    torque). In contact (η ≤ 0) it raises ValueError naming the time: the field is undefined there.
    """

    def __init__(self, robot: Robot, goal: Any, center: Callable[[float], Any], radius: float,
                 k_a: float, k_r: float, eta0: float, K_D: Any, gamma: float = 2.0):
        self.robot = robot
        self.goal = as_vector(goal, 2, "goal")
        if not callable(center):
            raise ValueError("`center` must be a function t -> (2,) obstacle position")
        self.center = center
        self.radius = as_positive(radius, "radius")
        self.k_a, self.k_r = as_positive(k_a, "k_a"), as_positive(k_r, "k_r")
        self.eta0, self.gamma = as_positive(eta0, "eta0"), as_positive(gamma, "gamma")
        self.K_D = np.broadcast_to(as_vector(np.atleast_1d(K_D), None, "K_D"), (robot.nv,)).astype(float)
        if np.any(self.K_D <= 0):
            raise ValueError(f"`K_D` must be positive, got {K_D}")
        self._model, self._data, self._ee = robot.model, robot.data, robot.ee_frame
        self._LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def __call__(self, t: float, meas: ArmMeasurement) -> np.ndarray:
        q, qd = meas.q, meas.qd
        model, data = self._model, self._data
        g = pin.computeGeneralizedGravity(model, data, q)
        J = pin.computeFrameJacobian(model, data, q, self._ee, self._LWA)[:2]     # also places the frames
        p_e = data.oMf[self._ee].translation[:2].copy()
        f_a = self.k_a * (self.goal - p_e)                                         # paraboloid, 12.6.1
        c = as_vector(self.center(t), 2, "center(t)")
        eta = planar_arm_obstacle_distance(self.robot, q, c, self.radius).distance
        if eta <= 0:
            raise ValueError(f"the arm touches the obstacle at t = {t:.4g} s (η = {eta:.3g} m)")
        tau_r = np.zeros(self.robot.nv)
        if eta < self.eta0:
            grad = planar_arm_obstacle_distance_gradient(self.robot, q, c, self.radius)   # ∂η/∂q = J_cᵀ∇η
            tau_r = float(repulsive_magnitude(eta, self.k_r, self.eta0, self.gamma)) * grad  # (12.15)
        tau = g + J.T @ f_a + tau_r - self.K_D * qd
        self.record(eta=eta, p_e=p_e, tau_r=tau_r, obstacle=c)
        return tau
