"""Crocoddyl's box-FDDP on a reach problem given as JSON on stdin; prints its result as JSON.

Run by ``benchmarks/bench_mpc.py`` with the Python of Crocoddyl's own environment (Crocoddyl 3 is built for
Pinocchio 3, the project uses Pinocchio 4)::

    python3 -m venv /tmp/croc
    /tmp/croc/bin/pip install crocoddyl 'pin<4' 'libpinocchio<4' 'cmeel-urdfdom<5' 'cmeel-tinyxml2<11'
    RMPC_CROCODDYL_PYTHON=/tmp/croc/bin/python python -m benchmarks --only mpc

It imports nothing from rmpc. The problem is the one of :func:`examples.optimal_control.reach_problem`: the URDF
(the locked joints fixed at 0), RK4 on N intervals of dt with the torque held, the costs
Σ dt·(RK4 quadrature of ℓ) + ℓ_N with ℓ = ½ w_p ‖p − p_d‖² + ½ w_o ‖log(R_dᵀ R)‖² + ½ Σ w_x (x − x_ref)² + ½ Σ w_τ τ²,
the torque box hard, no joint limit.
"""

import json
import sys
import time

import crocoddyl
import numpy as np
import pinocchio as pin


def main() -> None:
    spec = json.load(sys.stdin)
    full = pin.buildModelFromUrdf(spec["urdf"])
    lock = [full.getJointId(j) for j in spec.get("lock", []) if full.existJointName(j)]
    model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
    model.gravity = pin.Motion(np.array(spec["gravity"]), np.zeros(3))
    state = crocoddyl.StateMultibody(model)
    actuation = crocoddyl.ActuationModelFull(state)
    fid = model.getFrameId(spec["frame"])
    nu = model.nv

    def costs(w: dict, terminal: bool) -> crocoddyl.CostModelSum:
        c = crocoddyl.CostModelSum(state, nu)
        if w["position"] > 0:
            r = crocoddyl.ResidualModelFrameTranslation(state, fid, np.array(spec["p_d"]), nu)
            c.addCost("position", crocoddyl.CostModelResidual(state, r), w["position"])
        if w["orientation"] > 0:
            r = crocoddyl.ResidualModelFrameRotation(state, fid, np.array(spec["R_d"]), nu)
            c.addCost("orientation", crocoddyl.CostModelResidual(state, r), w["orientation"])
        r = crocoddyl.ResidualModelState(state, np.array(spec["x_ref"]), nu)
        c.addCost("state", crocoddyl.CostModelResidual(
            state, crocoddyl.ActivationModelWeightedQuad(np.array(w["state"])), r), 1.0)
        if not terminal:
            r = crocoddyl.ResidualModelControl(state, nu)
            c.addCost("effort", crocoddyl.CostModelResidual(
                state, crocoddyl.ActivationModelWeightedQuad(np.array(w["effort"])), r), 1.0)
        return c

    rk4 = crocoddyl.RKType.four
    running = crocoddyl.IntegratedActionModelRK(crocoddyl.DifferentialActionModelFreeFwdDynamics(
        state, actuation, costs(spec["running"], False)), rk4, spec["dt"])
    running.u_lb, running.u_ub = -np.array(spec["tau_max"]), np.array(spec["tau_max"])
    terminal = crocoddyl.IntegratedActionModelRK(crocoddyl.DifferentialActionModelFreeFwdDynamics(
        state, actuation, costs(spec["terminal"], True)), rk4, 0.0)
    x0 = np.array(spec["x0"])
    problem = crocoddyl.ShootingProblem(x0, [running] * spec["N"], terminal)
    xs0 = [x0.copy() for _ in range(spec["N"] + 1)]
    us0 = [np.array(u) for u in spec["us_init"]]
    times, cpu_times, solver = [], [], None
    for _ in range(spec.get("repeats", 5)):
        solver = crocoddyl.SolverBoxFDDP(problem)
        solver.th_stop = spec.get("th_stop", 1e-9)
        start, start_cpu = time.perf_counter(), time.process_time()
        solver.solve(xs0, us0, spec.get("max_iter", 500), False)
        times.append(time.perf_counter() - start)
        cpu_times.append(time.process_time() - start_cpu)
    json.dump({"cost": solver.cost, "iterations": solver.iter, "times": times, "cpu_times": cpu_times,
               "crocoddyl": crocoddyl.__version__,
               "us": [list(u) for u in solver.us]}, sys.stdout)


if __name__ == "__main__":
    main()
