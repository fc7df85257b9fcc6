"""Benchmark of the closed-form inverse kinematics of Sect. 2.12, relative to one raw Pinocchio FK call.

Each closed-form IK returns all its solutions and checks every one against the DH product (2.52);
the ratio is to one ``pin.forwardKinematics`` + ``pin.updateFramePlacement`` on the same robot,
measured in the same run. Also times the rotation conversions of ``rigid_body.rotations`` against
``pin.log3`` / ``pin.Quaternion``.

Run: ``python benchmarks/bench_closed_form_ik.py``.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from rigid_body import kinematics as kin
from rigid_body import rotations as rot
from rigid_body.robots import load

from benchtools import per_call


def raw_fk(robot, q):
    def f():
        pin.forwardKinematics(robot.model, robot.data, q)
        pin.updateFramePlacement(robot.model, robot.data, robot.ee_frame)
    return f


def rows(quick: bool = False) -> list[dict]:
    """Each closed-form IK (all solutions, each checked by the DH product) against one raw FK call, and the
    rotation conversions against Pinocchio's (no target: informative)."""
    reps = 400 if quick else 2000
    rng = np.random.default_rng(0)
    cases = {
        "planar_3r": lambda T: kin.inverse_kinematics_planar_3r([T[0, 3], T[1, 3], np.arctan2(T[1, 0], T[0, 0])]),
        "scara": lambda T: kin.inverse_kinematics_scara([*T[:3, 3], np.arctan2(T[1, 0], T[0, 0])]),
        "anthropomorphic": lambda T: kin.inverse_kinematics_anthropomorphic(T[:3, 3]),
        "spherical_wrist": lambda T: kin.inverse_kinematics_spherical_wrist(T[:3, :3]),
        "anthropomorphic_wrist": lambda T: kin.inverse_kinematics_anthropomorphic_wrist(T),
    }
    out = []
    for name, ik in cases.items():
        robot = load(name)
        q = rng.uniform(robot.lower, robot.upper)
        T = kin.direct_kinematics(robot, q)
        t_ik = per_call(lambda: ik(T), reps)
        t_fk = per_call(raw_fk(robot, q), reps * 10)
        out.append(dict(measurement=f"closed-form IK {name}, all solutions checked [µs]", rmpc=t_ik * 1e6,
                        reference=t_fk * 1e6, ref_name="one raw Pinocchio FK", target=None))
    R = pin.exp3(np.array([0.3, -0.2, 0.9]))
    t_log = per_call(lambda: pin.log3(R), reps * 10)
    t_quat = per_call(lambda: pin.Quaternion(R), reps * 10)
    for label, f, ref, ref_name in (("rotation_to_axis_angle", lambda: rot.rotation_to_axis_angle(R), t_log, "pin.log3"),
                                    ("rotation_to_quaternion", lambda: rot.rotation_to_quaternion(R), t_quat,
                                     "pin.Quaternion"),
                                    ("rotation_to_euler_zyz", lambda: rot.rotation_to_euler_zyz(R), t_log, "pin.log3")):
        out.append(dict(measurement=f"{label} [µs]", rmpc=per_call(f, reps) * 1e6, reference=ref * 1e6,
                        ref_name=ref_name, target=None))
    return out


if __name__ == "__main__":
    from benchtools import print_rows

    print_rows(rows())
