"""Beyond the book: a rigid surface (Pinocchio's constrained dynamics) as the limit of the compliant one.

The Panda under compliance control (operational-space PD + gravity on the tool pose, Eq. 8.110)
presses its tool into a wall 2 cm behind the wall's surface. The wall is modelled twice:

* **rigid** — the tip cannot leave the plane: n·(p_e − o_r) = 0 is a bilateral holonomic constraint,
  and the arm moves by Pinocchio's constrained forward dynamics (``pin.forwardDynamics`` with the
  constraint Jacobian J_c = nᵀ J_P, the KKT system [B J_cᵀ; J_c 0] [q̈; −λ] = [τ − n; −J̇_c q̇ − stab.],
  Baumgarte-stabilised), λ the normal contact force;
* **compliant** — the :class:`~controllers.environment.CompliantPlane` of stiffness k, for k growing by
  decades.

(Pinocchio's constrained dynamics refuses mimic joints, so the book's two-link arm with rotors cannot
be used; the Panda of example-robot-data can.)

As k grows the compliant contact force tends to the rigid one, at rest as k_P k/(k_P + k)·d → k_P d
(Eq. 9.22) and along the whole transient. Run ``python -m examples.rigid_contact``.

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sects. 9.2, 9.5 (Eqs. (9.22), (9.60)–(9.62)).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin

from rmpc import (ArmInContact, ArmPlant, compliance_equilibrium, CompliantPlane, direct_kinematics,
                  OperationalPDGravity, Robot, simulate)
from controllers.plants import ArmMeasurement
from problems.common import label_axes, subplots
from problems.registry import Solution
from rigid_body.rotations import homogeneous_transform
from rigid_body.validation import as_positive, as_vector

T_C = 1e-3                                              # controller period and plant step [s]
TOOL = "panda_hand_tcp"
O_R = np.array([0.6, -0.1, 0.45])                         # a point of the wall [m]
NORMAL = np.array([-1.0, 0.0, 0.0])                       # its outward normal
DEPTH = 0.02                                              # x_d behind the wall [m]


class ArmOnRigidPlane:
    """An arm whose end-effector origin is held on the plane n·(p − p_0) = 0 (bilateral, frictionless).

    x = [q, q̇]; q̈ from ``pin.forwardDynamics`` (KKT) with J_c = nᵀ J_P and the drift
    J̇_c q̇ + 2α J_c q̇ + α² n·(p − p_0) (Baumgarte, ``alpha`` [1/s]). :meth:`contact_force` is the
    constraint's normal force λ on the arm (h_e = −λ n is the wrench the tip exerts on the plane).
    """

    def __init__(self, robot: Robot, point: Any, normal: Any, viscous_friction: Any = 0.0, alpha: float = 50.0,
                 frame: str | int | None = None):
        self.robot, self.fid = robot, robot.frame(frame)
        self.arm = ArmPlant(robot, viscous_friction=viscous_friction)   # state layout, friction, initial state
        self.n, self.nq = robot.nv, robot.nq
        self.point = as_vector(point, 3, "point").copy()
        nrm = as_vector(normal, 3, "normal")
        self.normal = nrm / np.linalg.norm(nrm)
        self.alpha = as_positive(alpha, "alpha")
        self.initial_state = self.arm.initial_state
        self.state_layout = self.arm.state_layout

    def _solve(self, x: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, float]:
        m, d, fid = self.robot.model, self.robot.data, self.fid
        q, qd = x[:self.nq], x[self.nq:]
        pin.forwardKinematics(m, d, q, qd, np.zeros(self.n))
        pin.computeJointJacobians(m, d, q)
        p = pin.updateFramePlacement(m, d, fid).translation
        J_c = (self.normal @ pin.getFrameJacobian(m, d, fid, pin.LOCAL_WORLD_ALIGNED)[:3]).reshape(1, -1)
        acc = pin.getFrameClassicalAcceleration(m, d, fid, pin.LOCAL_WORLD_ALIGNED).linear
        a = self.alpha
        gamma = np.array([self.normal @ acc + 2 * a * float((J_c @ qd)[0]) + a * a * float(self.normal @ (p - self.point))])
        qdd = pin.forwardDynamics(m, d, q, qd, u - self.arm.Fv * qd, J_c, gamma, 0.0)
        return qdd.copy(), float(d.lambda_c[0])

    def derivative(self, t: float, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.concatenate([x[self.nq:], self._solve(x, u)[0]])

    def contact_force(self, x: np.ndarray, u: np.ndarray) -> float:
        """λ [N]: the normal force the plane exerts on the arm (positive = pushing the arm out)."""
        return self._solve(x, u)[1]

    def measure(self, t: float, x: np.ndarray) -> ArmMeasurement:
        return ArmMeasurement(x[:self.nq], x[self.nq:])


def rigid_versus_compliant(stiffnesses: tuple[float, ...] = (1e3, 1e4, 1e5, 1e6), duration: float = 1.0) -> Solution:
    """Compliance control pressing the Panda's tool into a wall, rigid (constrained dynamics) vs compliant."""
    from controllers.scenes import panda_wall

    sol = Solution(id="rigid-contact", title="Rigid wall (constrained dynamics) as the limit of a compliant one",
                   kind="simulation")
    scene = panda_wall()
    panda, R0, q0 = scene.panda, scene.R0, scene.q0
    p_start = direct_kinematics(panda, q0, TOOL)[:3, 3]
    p_start = p_start - float(NORMAL @ (p_start - O_R)) * NORMAL        # the tool on the wall's surface
    from planners.inverse_kinematics import solve_clik
    from rigid_body.task_space import TaskSpace

    q0 = solve_clik(panda, homogeneous_transform(R0, p_start), q0, TaskSpace(TOOL, "axis_angle")).q
    T_d = homogeneous_transform(R0, p_start - DEPTH * NORMAL)
    K_P = np.r_[1000.0, 1000.0, 1000.0, 100.0, 100.0, 100.0]
    ctrl = OperationalPDGravity(panda, K_P, np.r_[200.0, 200.0, 200.0, 10.0, 10.0, 10.0], T_d, frame=TOOL,
                                orientation="quaternion", joint_damping=2.0)
    rigid = ArmOnRigidPlane(panda, O_R, NORMAL, frame=TOOL)
    res_r = simulate(rigid, ctrl, (0.0, duration), rigid.initial_state(q0), h=T_C, Ts=T_C,
                     log=lambda t, x, u: {"f_n": rigid.contact_force(x, u)})
    f_rigid = res_r["f_n"]
    drift = float(np.abs((res_r["p_e"] - O_R) @ NORMAL).max())
    sol.value("constraint_violation_max", drift)
    sol.check("rigid: the tool stays on the wall (Baumgarte-stabilised constrained dynamics)", drift < 1e-6,
              f"max |n·(p − o_r)| = {drift:.1e} m")
    k_P = K_P[0]
    sol.check_close("rigid: rest force k_P d (the k → ∞ limit of (9.22)) [N]", f_rigid[-1], k_P * DEPTH, atol=0.05)
    deviations, runs = [], {}
    for k in stiffnesses:
        plant = ArmInContact(panda, CompliantPlane(O_R, NORMAL, k), frame=TOOL)
        res = simulate(plant, ctrl, (0.0, duration), plant.initial_state(q0), h=T_C, Ts=T_C,
                       log=lambda t, x, u, plant=plant: {"f_n": -plant.wrench(x[:7], x[7:])[0][:3] @ NORMAL})
        runs[k] = res
        deviations.append(float(np.mean(np.abs(res["f_n"] - f_rigid))))      # the rigid force jumps at t = 0
        h_pred, _ = compliance_equilibrium(k_P * np.eye(3), k * np.outer(NORMAL, NORMAL), -DEPTH * NORMAL)
        sol.check_close(f"k = {k:g} N/m: rest force = (9.22) [N]", res["f_n"][-1], -h_pred @ NORMAL, atol=0.05)
    sol.value("stiffness", np.array(stiffnesses))
    sol.value("mean_force_deviation_from_rigid", np.array(deviations))
    ratios = [b / a for a, b in zip(deviations, deviations[1:])]
    sol.check("the compliant force tends to the rigid one as k grows (mean deviation at least halved per decade)",
              all(r < 0.5 ** np.log10(k1 / k0) for r, k0, k1 in zip(ratios, stiffnesses, stiffnesses[1:])),
              f"mean |f_k − f_rigid| = {', '.join(f'{v:.3g}' for v in deviations)} N for k = {stiffnesses}")
    fig, ax = subplots(figsize=(6.4, 3.6))
    ax.plot(res_r.t, f_rigid, "k-", lw=2, label="rigid (constrained dynamics)")
    for k, r in runs.items():
        ax.plot(r.t, r["f_n"], "--", label=f"compliant, k = {k:g} N/m")
    label_axes(ax, "t [s]", "normal contact force [N]")
    sol.figure(fig, "Panda pressing into a wall under compliance control: rigid vs compliant contact")
    return sol


if __name__ == "__main__":
    result = rigid_versus_compliant()
    for c in result.checks:
        print(f"[{'PASS' if c.passed else 'FAIL'}] {c.name}: {c.detail}")
