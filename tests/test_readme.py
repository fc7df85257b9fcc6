"""The README keeps its promises: the library example runs, and the two set-up commands are the CI's."""

import re
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()


def test_library_example_runs_and_gives_the_book_inertia():
    code = re.findall(r"```python\n(.*?)```", README, re.S)[0]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    np.testing.assert_allclose(namespace["B"], [[243.8891, 45.4396], [45.4396, 122.5]], atol=1e-4)
    assert namespace["panda"].nq == 7


def test_ci_runs_the_readme_test_command():
    commands = re.findall(r"```bash\n(.*?)\n```", README, re.S)
    assert len(commands) == 2 and "rmpc report" in commands[0] and "pytest" in commands[1]
    assert commands[1] in (ROOT / ".ci" / "run").read_text()


def test_library_tour_runs_in_order_and_shows_what_it_says(tmp_path, monkeypatch):
    """Every ```python block of the README, executed in order in one namespace (the tour of twelve steps), in a
    temporary folder (step 10 writes a page)."""
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    blocks = re.findall(r"```python\n(.*?)```", README, re.S)
    assert len(blocks) >= 11
    ns: dict = {}
    for i, code in enumerate(blocks):
        exec(compile(code, f"README.md python block {i + 1}", "exec"), ns)
    np.testing.assert_allclose(ns["gravity_torques"](ns["arm"], np.zeros(2)), [98.1, 24.525])  # m g l/2 by hand
    assert ns["ik"].success and ns["ik"].residual < 1e-6
    assert ns["tip"].success  # position-only IK of a 3-DOF arm, checked against the direct kinematics
    np.testing.assert_allclose(ns["direct_kinematics"](ns["elbow"], ns["tip"].q)[:3, 3], [0.4, 0.2, 0.3], atol=1e-6)
    # the minimum time beats the 2 s quintic and reaches a torque limit
    assert ns["fastest"].success and ns["fastest"].t_f < 2.0 and ns["fastest"].ratios["tau"] > 0.99
    np.testing.assert_allclose(ns["res_pd"].q[-1], ns["q_f"], atol=2e-3)   # PD + g reaches its set point
    assert np.abs(ns["res_id"]["e"]).max() < 1e-2                           # computed torque tracks
    np.testing.assert_allclose(ns["res_pd_panda"].q[-1], ns["ik"].q, atol=1e-3)  # the Panda's gains converge
    assert np.abs(ns["res_ct_panda"]["e"]).max() < 1e-3
    np.testing.assert_allclose(ns["res_ct_panda"].q[-1], ns["ik"].q, atol=1e-4)
    assert ns["extra"][3] > 0 and np.abs(ns["extra"]).max() < 2.0 * 9.81     # at most m g · 1 m on the Panda
    assert repr(ns["arm"]).count("\n") == 0 and len(repr(ns["res_id"])) < 200
    # 7. force control: 20 N held while sliding, lost past the edge, regained; the plot names f_x … μ_z
    res_force, t = ns["res_force"], ns["res_force"].t
    f_n = -ns["res_force"]["h_e"][:, :3] @ ns["at_wall"].n                  # the push along the wall's normal
    assert np.abs(f_n[(t > 1.3) & (t < 1.9)] - 20.0).max() < 0.5 and np.any(f_n[(t > 2.0) & (t < 2.6)] == 0.0)
    assert abs(f_n[-1] - 20.0) < 0.1
    assert [label for label, _ in res_force.describe("h_e")] == ["f_x", "f_y", "f_z", "μ_x", "μ_y", "μ_z"]
    # 8. IBVS: the image back at s_d (a camera pose that sees it), the points in the 640 × 480 image throughout
    assert ns["ibvs"].image_error(ns["res_vs"])[-1] < 1e-3
    assert np.all(np.isfinite(ns["ibvs"].image_error(ns["res_vs"])))
    assert ns["res_vs"].describe("e_s")[:2] == [("x₁", "1"), ("y₁", "1")]
    # 9. the unicycle on the figure-eight, then parked at the origin
    assert ns["tracked"]["position_error"][-1] < 1e-3 and np.abs(ns["parked"].x[-1]).max() < 1e-2
    # 10. planned, certified, timed, certified, exported (a self-contained page)
    assert ns["found"].certified and ns["motion"].certified and ns["motion"].t_f > 0
    assert ns["page"].stat().st_size > 500_000 and len(repr(ns["motion"])) < 250
    # 11. the optimal control problem solved and checked; MPC reaches the set point with no failed sample
    assert ns["plan"].success and ns["plan"].kkt < 1e-6
    np.testing.assert_allclose(ns["res_mpc"].q[-1], [0.3, -0.2], atol=1e-2)
    assert ns["res_mpc"]["failed"].sum() == 0
    # 12. a law written once: the Python and the compiled loop agree; it reaches q_f
    np.testing.assert_allclose(ns["python_run"].q, ns["compiled_run"].q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ns["python_run"].q[-1], ns["q_f"], atol=2e-3)
