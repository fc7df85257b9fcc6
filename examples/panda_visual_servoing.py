"""Beyond the book: image-based visual servoing with a camera on the Panda's hand (Sect. 10.7.2).

The camera frame is ``panda_hand`` (z along the approach axis, the optical axis); it looks down at four
points, the corners of a 0.2 m square on the table plane, and must bring their images to where they are
seen from 0.5 m above the square's centre. The law is the resolved-velocity IBVS of Fig. 10.17 with the
eight point coordinates (10.26) and the full camera twist: q̇_r = J_L^† K_s e_s, J_L = L_s J_c (8×7, a
damped least-squares inverse), the arm modelled as an integrator (its joint velocity loop ideal).
The camera is a 640 × 480 pinhole (f α = 600 pixels): points outside the image are not seen.

Runs: (1) from a start rotated by 60° about the optical axis and offset by 0.2 m, depth known;
(2) the same with image noise (σ = 1 pixel) and one point occluded for 1 s — rows of unseen points are
dropped, the law degrades and recovers; (3) the classic camera retreat: a start rotated by π about the
optical axis. There the error of each point is radial (s_d = −s), so the least-squares twist is a pure
motion along −z_c: the camera backs away along its axis instead of rotating (Chaumette, "Potential
problems of stability and convergence in image-based and position-based visual servoing", 1998).

Run it from a notebook or ``python -m examples.panda_visual_servoing``; it returns a
:class:`problems.registry.Solution` (values, checks, figures) like a book problem.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rmpc import (direct_kinematics, eye_in_hand_ibvs, EyeInHandCamera, HybridVisualServo, KinematicArm,
                  PBVSPoseResolvedVelocity, PinholeCamera, simulate, SimulationResult, view_target,
                  visual_servo)
from controllers.scenes import CameraTarget, panda_camera_target
from controllers.visual_servoing import EyeInHandLoop
from problems.common import label_axes, subplots
from problems.registry import Solution
from viewer import eye_in_hand_animation

CAMERA = PinholeCamera(600.0, 600.0, 320.0, 240.0)
FOV = CAMERA.field_of_view(640, 480)
FRAME = "panda_hand"
Q_DESIRED_GUESS = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 1.9, np.pi / 4])
DEPTH = 0.5          # desired distance of the camera from the plane [m]
SIDE = 0.2           # side of the square [m]
TC = 0.02            # vision/controller period [s]
K_S = 1.0
DAMPING = 1e-2       # λ of the damped least-squares inverse of J_L (8×7): defined through the occlusion and the retreat


def scene() -> CameraTarget:
    """The Panda, the four points on the table and the desired camera pose (0.5 m above their centre):
    :func:`controllers.scenes.panda_camera_target`."""
    return panda_camera_target(SIDE, DEPTH, Q_DESIRED_GUESS)


def start_configuration(sc: CameraTarget, angle: float, offset_c: Any) -> np.ndarray:
    """Joints placing the camera at T_d · (rotation ``angle`` about z_c, translation ``offset_c`` in the camera frame)."""
    return sc.start(angle, offset_c)


def ibvs_loop(sc: CameraTarget, noise: float = 0.0, lost=None, depth: float | None = None,
              seed: int = 10) -> EyeInHandLoop:
    """Resolved-velocity IBVS of the four points (:func:`controllers.visual_servoing.eye_in_hand_ibvs`): the
    640 × 480 camera, K_s, T_c and the damping of this module."""
    return eye_in_hand_ibvs(sc.robot, sc.points_b, sc.T_d, frame=FRAME, camera=CAMERA, image_size=(640, 480), K_s=K_S,
                            Tc=TC, depth=depth, damping=DAMPING, noise=noise, rng=np.random.default_rng(seed), lost=lost)


def run_ibvs(sc: CameraTarget, q0: np.ndarray, t_f: float, noise: float = 0.0, lost=None,
             depth: float | None = None, seed: int = 10) -> SimulationResult:
    """Resolved-velocity IBVS with the four points from ``q0`` for ``t_f`` seconds."""
    return ibvs_loop(sc, noise, lost, depth, seed).run(q0, t_f)


def run_hybrid(sc: CameraTarget, q0: np.ndarray, t_f: float, K_p: float = 1.0, K_o: float = 1.0) -> SimulationResult:
    """2½-D visual servoing (:class:`HybridVisualServo`) with the four points from ``q0`` for ``t_f`` seconds:
    the plane's normal in the desired camera frame is its optical axis (the square faces the camera)."""
    xy_d = view_target(sc.T_d, sc.points_b).xy
    z_d = float((sc.points_b[0] - sc.T_d[:3, 3]) @ sc.T_d[:3, 2])
    camera = EyeInHandCamera(sc.robot, sc.points_b, FRAME, fov=FOV)
    law = HybridVisualServo(sc.robot, xy_d, [0.0, 0.0, 1.0], z_d, K_p, K_o, frame=FRAME)
    return simulate(KinematicArm(), visual_servo(camera, law, TC), (0.0, t_f), q0, h=TC, Ts=TC)


def run_pbvs(sc: CameraTarget, q0: np.ndarray, t_f: float, K_p: float = 1.0, K_o: float = 1.0) -> SimulationResult:
    """6-DOF resolved-velocity PBVS (:class:`PBVSPoseResolvedVelocity`) with the four points from ``q0``: the
    object frame is the square's (centre, axes of the desired camera), so T_o^d = [I, (0, 0, 0.5)]."""
    centre = sc.points_b.mean(axis=0)
    zeta = (sc.points_b - centre) @ sc.T_d[:3, :3]
    T_do = np.eye(4)
    T_do[:3, 3] = [0.0, 0.0, DEPTH]
    camera = EyeInHandCamera(sc.robot, sc.points_b, FRAME, fov=FOV)
    law = PBVSPoseResolvedVelocity(sc.robot, zeta[:, :2], T_do, K_p, K_o, frame=FRAME)
    return simulate(KinematicArm(), visual_servo(camera, law, TC), (0.0, t_f), q0, h=TC, Ts=TC)


def views(sc: CameraTarget, res: SimulationResult) -> list:
    """The (noise-free) view of the points at every sample, with the field of view."""
    return [view_target(direct_kinematics(sc.robot, q, FRAME), sc.points_b, FOV) for q in res.q]


def camera_depth(sc: CameraTarget, res: SimulationResult) -> np.ndarray:
    """Distance of the camera from the target plane along the plane's normal [m]."""
    n, c = sc.T_d[:3, 2], sc.points_b.mean(axis=0)
    return np.array([float(n @ (c - direct_kinematics(sc.robot, q, FRAME)[:3, 3])) for q in res.q])


def angle_about_axis(sc: CameraTarget, res: SimulationResult) -> np.ndarray:
    """Rotation of the camera about its optical axis relative to the desired pose [rad]."""
    out = []
    for q in res.q:
        R = sc.T_d[:3, :3].T @ direct_kinematics(sc.robot, q, FRAME)[:3, :3]
        out.append(np.arctan2(R[1, 0], R[0, 0]))
    return np.array(out)


def panda_ibvs() -> Solution:
    """IBVS of a camera on the Panda's hand: convergence, field of view, joint limits, noise, a lost
    point, and the camera retreat for a rotation of π about the optical axis."""
    sol = Solution(id="panda-ibvs", title="Panda: image-based visual servoing with an eye-in-hand camera",
                   kind="simulation")
    sc = scene()
    robot = sc.robot
    s_d = np.concatenate([v for v in view_target(sc.T_d, sc.points_b).xy])
    offset = 0.2 * np.array([0.4, -0.3, -0.85]) / np.linalg.norm([0.4, -0.3, -0.85])
    q0 = start_configuration(sc, np.pi / 3, offset)
    res = run_ibvs(sc, q0, 8.0)
    vs = views(sc, res)
    e_final = np.max(np.abs(np.concatenate(list(vs[-1].xy)) - s_d))
    sol.value("image_error_final", e_final)
    sol.check_error("60° + 0.2 m start: image error after 8 s", e_final, 1e-3)
    T_end = direct_kinematics(robot, res.q[-1], FRAME)
    sol.check_error("… and the camera pose reached = desired pose (position [m])",
                    np.linalg.norm(T_end[:3, 3] - sc.T_d[:3, 3]), 2e-3)
    sol.check("the four points stay inside the 640 × 480 image at every sample", all(v.all_visible for v in vs),
              f"{sum(not v.all_visible for v in vs)} samples with a point outside")
    lo, hi = robot.lower, robot.upper
    sol.check("joint limits respected at every sample", np.all((res.q >= lo) & (res.q <= hi)),
              f"min margin {np.min(np.minimum(res.q - lo, hi - res.q)):.3f} rad")
    e = res["e_s"]
    norm = np.linalg.norm(e, axis=1)
    ratio = norm[int(2.0 / TC)] / norm[int(1.0 / TC)]
    sol.value("error_ratio_1s", ratio)
    sol.check("the image error decays at the rate of the gain: ‖e(2 s)‖/‖e(1 s)‖ ≈ e^{−K_s} (±0.05)",
              abs(ratio - np.exp(-K_S)) < 0.05, f"{ratio:.4f} vs {np.exp(-K_S):.4f}")

    degraded = run_ibvs(sc, q0, 8.0, noise=1.0 / CAMERA.f_alpha_x, lost={0: (1.0, 2.0)})
    vd = views(sc, degraded)
    e_deg = np.max(np.abs(np.concatenate(list(vd[-1].xy)) - s_d))
    lost_rows = np.isnan(degraded["e_s"][:, 0])
    sol.value("image_error_final_noisy", e_deg)
    sol.check("point 1 occluded for 1 s: its rows dropped (NaN error) exactly then",
              np.array_equal(lost_rows, (degraded.t >= 1.0) & (degraded.t < 2.0)), f"{lost_rows.sum()} samples")
    sol.check_error("noise σ = 1 pixel and the occlusion: final image error (noise-free view)", e_deg, 5e-3)
    sol.check("… with the points in the image and the joints within limits throughout",
              all(v.all_visible for v in vd) and np.all((degraded.q >= lo) & (degraded.q <= hi)), "")

    q_pi = start_configuration(sc, np.pi, np.zeros(3))
    retreat = run_ibvs(sc, q_pi, 1.2, depth=DEPTH)
    z = camera_depth(sc, retreat)
    turn = angle_about_axis(sc, retreat)
    sol.value("retreat_depth_max", float(z.max()))
    sol.check("rotation by π about the optical axis: the camera retreats (depth grows > 0.2 m) ...",
              z.max() - DEPTH > 0.2, f"depth {DEPTH} → {z.max():.3f} m")
    sol.check("… without turning: the rotation about the axis stays at π (±0.05 rad)",
              np.max(np.abs(np.abs(turn) - np.pi)) < 0.05, f"max |Δ| = {np.max(np.abs(np.abs(turn) - np.pi)):.3g}")

    fig, axes = subplots(1, 3, figsize=(14, 4))
    xy = np.array([v.xy for v in vs])
    for i in range(4):
        axes[0].plot(xy[:, i, 0], xy[:, i, 1], label=f"P{i + 1}")
        axes[0].plot(*xy[0, i], "kx")
        axes[0].plot(*s_d[2 * i:2 * i + 2], "ko", mfc="none")
    axes[0].add_patch(__import__("matplotlib.patches", fromlist=["Rectangle"]).Rectangle(
        (FOV.x_min, FOV.y_min), FOV.x_max - FOV.x_min, FOV.y_max - FOV.y_min, fill=False, ls="--", color="gray"))
    axes[0].set_aspect("equal")
    label_axes(axes[0], "x [-] (normalised)", "y [-] (normalised)", title="image paths (start ×, goal ○)",
               legend=True)
    axes[1].semilogy(res.t, norm, label="noise-free")
    axes[1].semilogy(degraded.t, np.linalg.norm(np.nan_to_num(degraded["e_s"]), axis=1), label="noise + occlusion")
    label_axes(axes[1], "t [s]", "‖e_s‖ [-]", legend=True)
    axes[2].plot(retreat.t, z, label="depth of the plane [m]")
    axes[2].plot(retreat.t, np.abs(turn), label="|rotation about z_c| [rad]")
    label_axes(axes[2], "t [s]", "depth [m], angle [rad]", title="start rotated by π: retreat", legend=True)
    sol.figure(fig, "Panda IBVS — image paths, error norm, camera retreat")
    sol.animation(robot, title="IBVS from 60° and 0.2 m off: the hand camera's 640 × 480 viewing pyramid (to the "
                  "target plane) and the rays to the four points",
                  **eye_in_hand_animation(robot, res, sc.points_b, frame=FRAME,
                                          half_width=(CAMERA.X0 / CAMERA.f_alpha_x, CAMERA.Y0 / CAMERA.f_alpha_y),
                                          depth=DEPTH))
    return sol


if __name__ == "__main__":
    s = panda_ibvs()
    for c in s.checks:
        print("✔" if c.passed else "✘", c.name, c.detail)
