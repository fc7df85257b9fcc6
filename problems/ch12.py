"""Chapter 12 — Motion planning: Problems 12.1–12.13 (Figs. S12.1–S12.7).

Each problem builds its scene, calls the planners (``planners.configuration_space``, ``planners.cells``,
``planners.sampling``, ``planners.potentials``) and checks the result against an independent
reference: closed forms evaluated separately, a second algorithm (brute-force lifts on the torus,
scipy's Dijkstra, membership by sampling, a 2-D root finder against a scalar brentq), and, for every
planned path, a collision certificate on a dense re-sampling (clearance at the samples against a bound
on how far the robot moves between them).

Scenes: 12.7, 12.8 and 12.13 from the authors' companion files (s12_7, s12_8, s12_13); 12.3, 12.6,
12.10, 12.11 constructed here to show the stated effect; 12.4, 12.5 and 12.12 defined here (the book's
figures are not transcribed). Errata: 12.2 (the √2π claim), 12.10 (the single-disc point is a saddle),
12.11 (the sign of the force balance).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009, Chapter 12,
and its solution manual.
"""

from __future__ import annotations

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from scipy.spatial.distance import directed_hausdorff
from matplotlib.patches import Polygon as PolygonPatch

from controllers.scenes import grid_12_13, scene_12_7, scene_12_8
from planners.cells import (channel_path, gvd_nodes, polyline_clearance, quadtree_decomposition,
                            sampled_gvd, trapezoidal_decomposition, visibility_graph)
from planners.configuration_space import (Disc, PlanarArm, PlanarCSpace, Polygon, Scene, box,
                                    certify_motion, certify_straight_path, connected_components, densify, free_grid,
                                    euclidean_distance,
                                    minkowski_c_obstacle, point_segment_distance, point_shape_distance,
                                    shapes_intersect, torus_distance, transform_shape)
from planners.potentials import (AttractivePotential, PotentialField, RepulsivePotential,
                                 gradient_descent, range_scan, reactive_repulsive_force, repulsive_magnitude,
                                 scan_segments,
                                 stationary_point, steepest_descent_path, wavefront, grid_path_length)
from planners.sampling import (MotionPrimitive, path_length, prm, rrt_connect, shortcut,
                               unicycle_arc, unicycle_rrt)
from problems.common import label_axes, max_error, subplots
from problems.registry import Solution, problem

SEED = 12  # one seed for every randomised problem


# --------------------------------------------------------------------------------------------
# Scenes (those of 12.7, 12.8 and 12.13 live in controllers.scenes, for the benchmarks and a user)
# --------------------------------------------------------------------------------------------

def scene_12_4() -> Scene:
    """Defined here (Fig. 12.4 is not transcribed): two small discs near the base of the 2R arm of
    12.7, at 0.6 m and polar angles 3.55 and 4.70 rad. Link 1 cannot pass them and link 2, folded back,
    cannot either: C_free splits into three components."""
    pol = lambda r, a: [r * np.cos(a), r * np.sin(a)]  # noqa: E731
    return Scene([Disc(pol(0.6, 3.55), 0.12), Disc(pol(0.6, 4.70), 0.12)], (-2.2, 2.2, -2.2, 2.2))


def given_obstacles(sol: Solution, shapes: list, name: str = "obstacles") -> None:
    """Declare a scene's obstacles as data of the problem: the discs as rows [x, y, r], each polygon's vertices."""
    discs = [np.r_[s.center, s.radius] for s in shapes if isinstance(s, Disc)]
    polygons = [s.vertices for s in shapes if not isinstance(s, Disc)]
    if discs:
        sol.given(f"{name}: discs [x, y, r]", np.array(discs), unit="m")
    for k, vertices in enumerate(polygons, start=1):
        sol.given(f"{name}: polygon {k}", np.asarray(vertices, dtype=float), unit="m")


# --------------------------------------------------------------------------------------------
# Drawing and verification helpers
# --------------------------------------------------------------------------------------------

def draw_shapes(ax, shapes, **kw) -> None:
    """Draw discs and polygons on a matplotlib Axes."""
    kw = {"facecolor": "0.6", "edgecolor": "k", "lw": 0.8} | kw
    for k, s in enumerate(shapes):
        if k == 1:
            kw.pop("label", None)   # one legend entry per call
        if isinstance(s, Disc):
            ax.add_patch(Circle(s.center, s.radius, **kw))
        else:
            ax.add_patch(PolygonPatch(s.vertices, closed=True, **kw))


def _workspace_axes(ax, bounds, title: str) -> None:
    ax.set_xlim(bounds[0], bounds[1])
    ax.set_ylim(bounds[2], bounds[3])
    ax.set_aspect("equal")
    label_axes(ax, "x [m]", "y [m]", title=title, legend=False, grid=False)


def _potential_figure(sol: Solution, fig, ax, goal, bounds, title: str, legend_loc: str) -> Solution:
    """Close a potential-field figure (12.11, 12.12): the goal marked, workspace axes, legend; attach it."""
    ax.plot(*goal, "g*", ms=12, label="goal")
    _workspace_axes(ax, bounds, "")
    ax.legend(loc=legend_loc, fontsize=7)
    sol.figure(fig, title)
    return sol


def _cspace_axes(ax, title: str) -> None:
    label_axes(ax, "q₁ [rad]", "q₂ [rad]", title=title, legend=False, grid=False)


def _torus_grid(space: PlanarCSpace, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Free map of the 2R torus on an n × n grid over [−π, π)², and the grid axis."""
    axis = np.linspace(-np.pi, np.pi, n, endpoint=False)
    return free_grid(space, [axis, axis]), axis


# --------------------------------------------------------------------------------------------
# 12.1–12.4: configuration space
# --------------------------------------------------------------------------------------------

@problem("12.1", "Configuration space of a unicycle carrying a 6R manipulator", kind="derivation")
def problem_12_1() -> Solution:
    """Give the configuration space of a mobile manipulator: a unicycle carrying a six-revolute arm.

    The model is built, not typed: a Pinocchio planar joint (x, y, θ0 — the unicycle's posture in
    R² × SO(2), nq = 4 as (x, y, cos θ0, sin θ0), nv = 3) carrying the book's six-joint anthropomorphic
    arm with spherical wrist (``urdf/anthropomorphic_wrist.urdf``) through ``pin.appendModel``.
    dim C = nv, the number of independent coordinates; the manual's answer is
    q = [x y θ0 θ1 … θ6], C = R² × SO(2)⁷, dimension 9. Checked: the joint structure, and that the 9
    coordinates are independent: the placements of all the bodies vary along 9 independent directions
    (the rank of their central differences along the 9 tangent directions, through ``pin.integrate``).
    """
    import pinocchio as pin

    from rigid_body.robots import load

    sol = Solution()
    base = pin.Model()
    base.addJoint(0, pin.JointModelPlanar(), pin.SE3.Identity(), "unicycle")
    base.addFrame(pin.Frame("platform", 1, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    arm = load("anthropomorphic_wrist")
    model = pin.appendModel(base, arm.model, base.getFrameId("platform"), pin.SE3.Identity())
    dim = sol.value("dim_C", int(model.nv), unit="1")
    sol.value("nq", int(model.nq), unit="1")
    kinds = [j.shortname() for j in model.joints[1:]]
    sol.value("joints", kinds)
    n_so2 = sum(k.startswith("JointModelR") for k in kinds) + sum(k == "JointModelPlanar" for k in kinds)
    n_r = 2 * sum(k == "JointModelPlanar" for k in kinds)
    sol.value("structure", f"R^{n_r} x SO(2)^{n_so2}")
    sol.check_close("C = R² × SO(2)⁷ (manual): 2 translations and 7 angles in the model's joints", [n_r, n_so2], [2, 7],
                    atol=0, reference="manual number")
    # independence: the placements of every body (position and log of the rotation) as functions of q, differenced
    # along each of the model's nv tangent directions at a random configuration
    data = model.createData()
    q0 = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))

    def placements(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, q)
        return np.concatenate([np.r_[M.translation, pin.log3(M.rotation)] for M in data.oMi[1:]])

    h = 1e-6
    J = np.column_stack([(placements(pin.integrate(model, q0, h * e)) - placements(pin.integrate(model, q0, -h * e)))
                         / (2 * h) for e in np.eye(model.nv)])
    rank = int(np.linalg.matrix_rank(J, tol=1e-6))
    sol.value("rank_of_body_placements", rank, unit="1")
    sol.check_close(f"dim C = 9 (manual): the bodies' placements vary along {dim} independent directions (rank of their "
                    "central differences along the model's tangent directions)", [rank, dim], [9, 9], atol=0,
                    reference="manual number")
    return sol


@problem("12.2", "A C-space distance for the 2R arm that respects the torus", kind="derivation")
def problem_12_2() -> Solution:
    """Define a configuration-space distance for the 2R arm consistent with the torus topology of C.

    Manual: Δ_i = min(|q_{i,A} − q_{i,B}|, 2π − |q_{i,A} − q_{i,B}|), d₃ = √(Δ1² + Δ2²). Checked against
    a second algorithm (the smallest Euclidean distance over the lifts q_B + 2πk, k ∈ {−1, 0, 1}²) and
    for the metric properties at random pairs. **Erratum:** the manual says d₃ = d₂ "whenever the
    Euclidean distance is not larger than √2π"; false — Δq = (1.2π, 0) has d₂ = 3.770 < √2π = 4.443 but
    d₃ = 2.513. The correct condition is |Δq_1| ≤ π and |Δq_2| ≤ π.
    """
    sol = Solution()
    rng = np.random.default_rng(SEED)
    A = rng.uniform(0, 2 * np.pi, (2000, 2))
    B = rng.uniform(0, 2 * np.pi, (2000, 2))
    C = rng.uniform(0, 2 * np.pi, (2000, 2))
    d3 = torus_distance(A, B)
    lifts = np.array([[i, j] for i in (-1, 0, 1) for j in (-1, 0, 1)]) * 2 * np.pi
    brute = np.min(np.linalg.norm(B[:, None, :] + lifts[None] - A[:, None, :], axis=-1), axis=1)
    sol.check_close("d₃ = min over the lifts q_B + 2πk of ‖q_A − q_B − 2πk‖ (2000 pairs)", d3, brute, atol=1e-12,
                    reference="second algorithm")
    sol.check("symmetric", np.allclose(d3, torus_distance(B, A), atol=1e-12))
    sol.check("triangle inequality d₃(A,C) ≤ d₃(A,B) + d₃(B,C)",
              np.all(torus_distance(A, C) <= d3 + torus_distance(B, C) + 1e-12))
    k = rng.integers(-3, 4, (2000, 2)) * 2 * np.pi
    sol.check("invariant to q ↦ q + 2πk", np.allclose(torus_distance(A + k, B), d3, atol=1e-9))
    d2 = euclidean_distance(A, B)
    sol.check("d₃ ≤ d₂", np.all(d3 <= d2 + 1e-12))
    inside = np.all(np.abs(A - B) <= np.pi, axis=1)
    sol.check("d₃ = d₂ exactly when |Δq_i| ≤ π for both joints",
              np.allclose(d3[inside], d2[inside], atol=1e-12) and np.all(d3[~inside] < d2[~inside]))
    # the erratum: a counterexample to the manual's √2π condition
    qa, qb = np.array([0.0, 0.0]), sol.given("counterexample q_B (q_A = 0)", np.array([1.2 * np.pi, 0.0]), unit="rad")
    c2, c3 = float(euclidean_distance(qa, qb)), float(torus_distance(qa, qb))
    sol.value("counterexample_dq", qb - qa, unit="rad")
    sol.value("counterexample_d2", c2, unit="rad")
    sol.value("counterexample_d3", c3, unit="rad")
    sol.check("erratum: d₂ = 3.770 ≤ √2π = 4.443 yet d₃ = 2.513 ≠ d₂ (the manual's claim is false)",
              c2 <= np.sqrt(2) * np.pi and abs(c3 - 0.8 * np.pi) < 1e-12 and c3 < c2 - 1,
              f"d₂ = {c2:.4f}, √2π = {np.sqrt(2) * np.pi:.4f}, d₃ = {c3:.4f}")
    within = d2 <= np.sqrt(2) * np.pi
    share = float(np.mean(d3[within] < d2[within] - 1e-12))
    sol.value("share_of_pairs_violating_claim", share, unit="1")
    # the exact share for uniform q_A, q_B: each |Δq_i| has the density (2π − δ)/(2π²) on [0, 2π); the claim fails
    # where d₂ ≤ √2π yet some |Δq_i| > π (scipy's dblquad over that region, relative to the disc d₂ ≤ √2π)
    from scipy.integrate import dblquad

    density = lambda d: (2 * np.pi - d) / (2 * np.pi**2)                                      # noqa: E731
    R = np.sqrt(2) * np.pi
    arc = lambda x: np.sqrt(max(R * R - x * x, 0.0))                                           # noqa: E731
    disc = dblquad(lambda y, x: density(x) * density(y), 0.0, R, 0.0, arc)[0]
    exact = 2 * dblquad(lambda y, x: density(x) * density(y), np.pi, R, 0.0, arc)[0] / disc
    sol.value("share_exact", exact, unit="1")
    sigma = np.sqrt(exact * (1 - exact) / within.sum())
    sol.check_close(f"the claim fails for a quarter of the pairs with d₂ ≤ √2π: the sampled share ({within.sum()} pairs) "
                    f"= the exact {exact:.4f} (scipy dblquad) within 4σ", share, exact, atol=4 * sigma,
                    reference="other library")
    sol.check("what is true: d₂ ≤ π implies d₃ = d₂", np.allclose(d3[d2 <= np.pi], d2[d2 <= np.pi], atol=1e-12))
    return sol


@problem("12.3", "Two different scenes with the same C-obstacle (translating robots)", kind="derivation")
def problem_12_3() -> Solution:
    """Find two robot/obstacle pairs, robots free to translate only, that give the same C-obstacle.

    Scene 1: triangle B1 = {(0,0), (1,0), (0,1)} and square O1 = [0, 2]²; scene 2: unit square B2 and
    pentagon O2 = {(0,1), (1,0), (2,0), (2,2), (0,2)} (reference point at the robots' origin). Both
    give CO = O ⊕ (−B) = the pentagon {(−1,0), (0,−1), (2,−1), (2,2), (−1,2)} (Fig. S12.1). Checked by
    a second method: a configuration q is in CO iff the robot placed at q touches the obstacle,
    sampled at random points.
    """
    sol = Solution()
    scenes = [(Polygon(sol.given("B1 (triangle)", np.array([[0.0, 0], [1, 0], [0, 1]]), unit="m")),
               Polygon(sol.given("O1 (square)", np.array([[0.0, 0], [2, 0], [2, 2], [0, 2]]), unit="m"))),
              (Polygon(sol.given("B2 (unit square)", np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]]), unit="m")),
               Polygon(sol.given("O2 (pentagon)", np.array([[0.0, 1], [1, 0], [2, 0], [2, 2], [0, 2]]), unit="m")))]
    COs = [minkowski_c_obstacle(O, B) for B, O in scenes]
    key = lambda P: np.array(sorted(map(tuple, np.round(P.vertices, 12))))  # noqa: E731
    sol.value("CO_vertices", key(COs[0]), unit="m")
    sol.check("both scenes give the same C-obstacle (same vertex set)",
              key(COs[0]).shape == key(COs[1]).shape and np.allclose(key(COs[0]), key(COs[1])))
    expected = np.array(sorted([(-1, 0), (0, -1), (2, -1), (2, 2), (-1, 2)]), dtype=float)
    sol.check_close("CO = pentagon {(−1,0), (0,−1), (2,−1), (2,2), (−1,2)} (constructed by hand)",
                    key(COs[0]), expected, atol=1e-12, reference="closed form")
    rng = np.random.default_rng(SEED)
    Qs = rng.uniform(-2, 3, (1500, 2))
    for k, ((B, O), CO) in enumerate(zip(scenes, COs), start=1):
        far = np.array([point_shape_distance(CO, q) > 1e-6 or CO.contains(q, -1e-6) for q in Qs])
        touch = np.array([shapes_intersect(transform_shape(B, q[0], q[1], 0.0), O) for q in Qs[far]])
        sol.check(f"scene {k}: q ∈ CO ⟺ B(q) ∩ O ≠ ∅ (the robot placed at q and intersected with O) at {far.sum()} "
                  "random q", np.array_equal(touch, CO.contains(Qs[far])), reference="second algorithm")
    fig, axes = subplots(2, 2, figsize=(9, 8))
    for row, ((B, O), CO) in enumerate(zip(scenes, COs)):
        ax = axes[row, 0]
        draw_shapes(ax, [O], facecolor="0.6", label="obstacle O")
        for v in O.vertices:       # the growing procedure: −B placed at every vertex of O
            draw_shapes(ax, [Polygon(v - B.vertices)], facecolor="none", edgecolor="tab:blue", lw=0.5, ls="--")
        draw_shapes(ax, [Polygon(B.vertices + [-1.8, -1.8])], facecolor="tab:blue", alpha=0.7, label="robot B")
        ax.plot(-1.8, -1.8, "k+", label="reference point")
        _workspace_axes(ax, (-2.5, 3, -2.5, 3), f"scene {row + 1}: robot and obstacle")
        ax.legend(loc="upper left", fontsize=7)
        ax = axes[row, 1]
        draw_shapes(ax, [CO], facecolor="tab:red", alpha=0.4, label="C-obstacle CO")
        draw_shapes(ax, [O], facecolor="0.6", alpha=0.6, label="O")
        _workspace_axes(ax, (-2.5, 3, -2.5, 3), f"scene {row + 1}: C-obstacle O ⊕ (−B)")
        ax.set_xlabel("reference point x [m]")
        ax.set_ylabel("reference point y [m]")
        ax.legend(loc="upper left", fontsize=7)
    sol.figure(fig, "Fig. S12.1 — two scenes with the same C-obstacle")
    return sol


@problem("12.4", "Three configurations of the 2R arm in disjoint components of C_free", kind="numeric")
def problem_12_4() -> Solution:
    """Find configurations in each of the three disjoint components of C_free of a 2R arm (Fig. 12.4).

    Manual: q_a = [π/4, π/2], q_b = [4.12, π/6], q_c = [4.12, 2.88] rad. Fig. 12.4's obstacles are not
    transcribed, so the scene is defined here (:func:`scene_12_4`) such that its C_free has three
    components. C_free is rasterised on the torus and labelled (scipy.ndimage.label plus the seams
    q_i = ±π glued); the count and the three memberships are confirmed on a grid twice as fine.
    """
    sol = Solution()
    scene = scene_12_4()
    given_obstacles(sol, scene.obstacles)
    arm = PlanarArm(tuple(sol.given("a1, a2", np.array([1.0, 1.0]), unit="m")), sol.given("link width", 0.1, unit="m"))
    space = PlanarCSpace(arm, scene, [-np.pi, -np.pi], [np.pi, np.pi])
    q = {"q_a": np.array([np.pi / 4, np.pi / 2]), "q_b": np.array([4.12, np.pi / 6]),
         "q_c": np.array([4.12, 2.88])}
    for name, q_k in q.items():
        sol.given(name, q_k, unit="rad")
    results = {}
    for n in (160, 320):
        free, axis = _torus_grid(space, n)
        labels, count = connected_components(free)
        cells = {k: tuple(np.round((np.mod(v + np.pi, 2 * np.pi) - np.pi + np.pi) / (2 * np.pi) * n).astype(int) % n)
                 for k, v in q.items()}
        results[n] = (count, {k: int(labels[c]) for k, c in cells.items()}, labels, axis)
    count, member, labels, axis = results[320]
    sol.value("components", count, unit="1")
    sol.value("labels", member, unit="1")
    clear = {k: float(scene.clearance(arm.bodies(v))) for k, v in q.items()}
    sol.value("clearance", clear, unit="m")
    sol.check_close("C_free has the manual's 3 disjoint components (0.04 rad and 0.02 rad grids)",
                    [results[160][0], count], [3, 3], atol=0, reference="manual number")
    sol.check("q_a, q_b, q_c are free (exact geometry)", min(clear.values()) > 0, str(clear))
    sol.check("q_a, q_b, q_c lie in three different components (both grids)",
              all(len(set(r[1].values())) == 3 and 0 not in r[1].values() for r in results.values()),
              f"{results[160][1]}, {member}")
    fig, axes = subplots(2, 3, figsize=(12, 9))
    colors = {"q_a": "tab:blue", "q_b": "tab:orange", "q_c": "tab:green"}
    for ax, (name, v) in zip(axes[0], q.items()):
        draw_shapes(ax, scene.obstacles, label="obstacles")
        draw_shapes(ax, arm.bodies(v), facecolor=colors[name], alpha=0.8)
        ax.plot(*arm.joint_positions(v).T, "k.-", lw=0.8, label=f"{name} = [{v[0]:.2f}, {v[1]:.2f}] rad")
        _workspace_axes(ax, scene.bounds, f"posture {name}")
        ax.legend(loc="upper right", fontsize=7)
    # the component map on the torus, q₂ shown over [0, 2π) so that q_c's component (around q₂ = π) is one piece;
    # each component in its configuration's colour, the C-obstacle dark, a zoom on the two small components
    gs = axes[1, 0].get_gridspec()
    for ax in axes[1]:
        ax.remove()
    big, zoom = fig.add_subplot(gs[1, :2]), fig.add_subplot(gs[1, 2])
    n = labels.shape[0]
    shown = np.roll(labels, -n // 2, axis=1).T                      # rows q₂ ∈ [0, 2π), columns q₁ ∈ [−π, π)
    palette = ["0.3"] + ["0.85"] * count
    for name, k in member.items():
        palette[k] = colors[name]
    cmap = ListedColormap(palette)
    for ax, title in ((big, "components of C_free on the torus (q₂ shown over [0, 2π))"),
                      (zoom, "zoom: the components of q_b and q_c")):
        ax.imshow(shown, origin="lower", extent=[-np.pi, np.pi, 0.0, 2 * np.pi], cmap=cmap, vmin=-0.5,
                  vmax=count + 0.5, interpolation="nearest", alpha=0.55)
        window = (-2.9, -1.0, 2.2, 4.1) if ax is zoom else (-np.pi, np.pi, 0.0, 2 * np.pi)
        for name, v in q.items():
            w = np.array([np.mod(v[0] + np.pi, 2 * np.pi) - np.pi, np.mod(v[1], 2 * np.pi)])
            if window[0] <= w[0] <= window[1] and window[2] <= w[1] <= window[3]:
                ax.plot(*w, "o", color=colors[name], mec="k", ms=7)
        ax.set_xlim(*window[:2])
        ax.set_ylim(*window[2:])
        _cspace_axes(ax, title)
    big.set_aspect("equal")
    keys = [PolygonPatch([[0, 0]], facecolor="0.3", alpha=0.55, label="C-obstacle")]
    keys += [PolygonPatch([[0, 0]], facecolor=colors[name], alpha=0.55, label=f"component of {name} (label {k})")
             for name, k in member.items()]
    big.legend(handles=keys, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=7)
    zoom.legend(handles=keys[:1] + keys[2:], loc="upper right", fontsize=7)
    sol.figure(fig, "Fig. S12.2 — configurations in the three components of C_free")
    return sol


# --------------------------------------------------------------------------------------------
# 12.5–12.6: roadmaps and cells
# --------------------------------------------------------------------------------------------

@problem("12.5", "A naive algorithm for the generalised Voronoi diagram", kind="derivation")
def problem_12_5() -> Solution:
    """Sketch an algorithm for the generalised Voronoi diagram of a bounded polygonal set.

    The manual's algorithm (equidistance curves of vertex/side pairs, their intersections, discard
    those outside, with unequal characteristic distances or with clearance ≠ that distance) is
    :func:`planners.cells.gvd_nodes`. On the rectangle [0, a] × [0, b], a > b, the GVD is the medial
    axis: the nodes are (b/2, b/2) and (a − b/2, b/2) (plus the corners, clearance 0). The diagram is
    also sampled with scipy's Voronoi of boundary points: every ridge must lie on the medial axis.
    """
    sol = Solution()
    a, b = sol.given("a", 4.0, unit="m"), sol.given("b", 1.5, unit="m")
    K = box(0, 0, a, b)
    nodes = gvd_nodes(K)
    inner = nodes[nodes[:, 2] > 1e-9]
    sol.value("nodes", inner[:, :2], unit="m")
    sol.check_close("nodes (b/2, b/2), (a − b/2, b/2), clearance b/2", inner,
                    [[b / 2, b / 2, b / 2], [a - b / 2, b / 2, b / 2]], atol=1e-9, reference="closed form")
    corners = nodes[nodes[:, 2] <= 1e-9, :2]
    sol.check_close("the other nodes are the four corners (clearance 0)",
                    np.array(sorted(map(tuple, np.round(corners, 9) + 0.0))),
                    np.array(sorted(map(tuple, K.vertices))), atol=1e-9, reference="closed form")
    segs = sampled_gvd(K, spacing=0.02)
    P = segs.reshape(-1, 2)
    x, y = P[:, 0], P[:, 1]
    on_spine = np.abs(y - b / 2) + np.maximum(0, np.maximum(b / 2 - x, x - (a - b / 2)))
    on_diag = np.minimum.reduce([np.abs(y - x), np.abs(y - (b - x)), np.abs(y - (x - a + b)), np.abs(y - (a - x))])
    err = float(np.max(np.minimum(on_spine, on_diag)))
    sol.value("sampled_gvd_max_distance_from_medial_axis", err, unit="m")
    sol.check_error("sampled GVD (scipy Voronoi of boundary points 0.02 m apart) lies on the medial axis [m]", err, 0.02,
                    reference="other library")
    # a room with an obstacle: the GVD around it
    room = box(*sol.given("room [x_min, y_min, x_max, y_max]", np.array([0.0, 0.0, 10.0, 6.0]), unit="m"))
    hole = Polygon(sol.given("obstacle in the room", np.array([[4.0, 2.0], [6.5, 2.5], [5.0, 4.0]]), unit="m"))
    nodes2 = gvd_nodes(room, [hole])
    segs2 = sampled_gvd(room, [hole], spacing=0.05)
    feats = [(p, q) for poly in (room, hole) for p, q in zip(*poly.edges)]
    mids = segs2.mean(axis=1)
    d = np.sort(np.array([[float(point_segment_distance(m, p, q)) for p, q in feats] for m in mids]), axis=1)
    gap = float(np.max(d[:, 1] - d[:, 0]))
    sol.check_error("room + obstacle: every sampled GVD point (scipy Voronoi) has two nearest sides equally far [m]",
                    gap, 0.05, reference="other library")
    sol.value("room_nodes", nodes2[nodes2[:, 2] > 1e-9, :2], unit="m")
    fig, axes = subplots(1, 2, figsize=(11, 4.6))
    for ax, (R, H, S, N, title) in zip(axes, [(K, [], segs, nodes, "rectangle: GVD = medial axis"),
                                             (room, [hole], segs2, nodes2, "room with an obstacle")]):
        draw_shapes(ax, [R], facecolor="none")
        draw_shapes(ax, H)
        for s in S:
            ax.plot(s[:, 0], s[:, 1], "tab:blue", lw=1)
        ax.plot([], [], "tab:blue", label="sampled GVD (scipy Voronoi)")
        ax.plot(N[N[:, 2] > 1e-9, 0], N[N[:, 2] > 1e-9, 1], "ro", label="nodes (naive algorithm)")
        _workspace_axes(ax, (R.vertices[:, 0].min() - 0.3, R.vertices[:, 0].max() + 0.3,
                             R.vertices[:, 1].min() - 0.3, R.vertices[:, 1].max() + 0.3), title)
        ax.legend(loc="upper right", fontsize=7)
    sol.figure(fig, "Problem 12.5 — generalised Voronoi diagrams")
    return sol


@problem("12.6", "Channel-to-path extraction in cell decomposition: the flaw and its fix", kind="derivation")
def problem_12_6() -> Solution:
    """Show that extracting a path from a channel through the midpoints of the common boundaries only
    can give a path touching an obstacle, and fix it.

    Scene (constructed here): workspace [0, 10]², diamond {(5,5), (6,4), (7,5), (6,6)}, start above it (5.5, 7), goal
    below (5.5, 3). The trapezoidal decomposition's channel is above → left cell → below; the midpoint path
    (5, 7.5) → (5, 2.5) runs along the cell boundary x = 5 through the vertex (5, 5): clearance 0. The fix
    (manual): insert the centroid of every channel cell except c_s and c_g — here (2.5, 5) — and the
    clearance becomes positive. An approximate (quadtree) decomposition and the visibility graph give
    comparisons; the visibility-graph length 2√(0.5² + 2²) is the shortest possible.
    """
    sol = Solution()
    diamond = Polygon(sol.given("obstacle vertices", np.array([[5, 5], [6, 4], [7, 5], [6, 6]]), unit="m"))
    qs, qg = sol.given("q_s", np.array([5.5, 7.0]), unit="m"), sol.given("q_g", np.array([5.5, 3.0]), unit="m")
    dec = trapezoidal_decomposition((0, 10, 0, 10), [diamond])
    naive, chan = channel_path(dec, qs, qg, centroids=False)
    fixed, _ = channel_path(dec, qs, qg, centroids=True)
    sol.value("cells", len(dec.cells), unit="1")
    sol.value("channel", chan, unit="1")
    sol.value("midpoint_path", naive, unit="m")
    sol.value("fixed_path", fixed, unit="m")
    c_naive, c_fixed = polyline_clearance(naive, [diamond]), polyline_clearance(fixed, [diamond])
    sol.value("clearance_midpoint_path", c_naive, unit="m")
    sol.value("clearance_fixed_path", c_fixed, unit="m")
    cells = [dec.cells[k] for k in chan]
    sol.check("channel = the cell holding q_s (above the diamond), the cell left of it (x ≤ 5), the cell holding q_g "
              "(below): located by point containment",
              len(chan) == 3 and bool(cells[0].contains(qs)) and bool(cells[2].contains(qg))
              and cells[1].vertices[:, 0].max() <= 5 + 1e-9 and bool(cells[1].contains(np.array([2.5, 5.0]))),
              str(chan), reference="closed form")
    sol.check_close("midpoint path: q_s, (5, 7.5), (5, 2.5), q_g", naive, [qs, [5, 7.5], [5, 2.5], qg], atol=1e-9,
                    reference="closed form")
    sol.check("midpoint path touches the obstacle's leftmost vertex (clearance 0)", c_naive == 0.0, f"{c_naive}",
              reference="closed form")
    sol.check_close("fixed path has 5 vertices, the left cell's centroid (2.5, 5) inserted", fixed,
                    [qs, [5, 7.5], [2.5, 5], [5, 2.5], qg], atol=1e-9, reference="closed form")
    # closed forms: the new edges pass (5, 5) at 2.5/√2; the path's clearance is then set by q_s, q_g
    d_vertex = min(float(point_segment_distance([5, 5], a, b)) for a, b in zip(fixed[1:-2], fixed[2:-1]))
    sol.check_close("fixed path: the edges through the centroid pass the vertex (5, 5) at 2.5/√2 = 1.768 m",
                    d_vertex, 2.5 / np.sqrt(2), atol=1e-12, reference="closed form")
    sol.check_close("fixed path clearance = distance of q_s from the vertex (6, 6) = √1.25 = 1.118 m",
                    c_fixed, np.sqrt(1.25), atol=1e-12, reference="closed form")
    quad = quadtree_decomposition((0, 10, 0, 10), [diamond], min_size=0.25)
    qpath, qchan = channel_path(quad, qs, qg)
    c_quad = polyline_clearance(qpath, [diamond])
    sol.value("quadtree_cells", len(quad.cells), unit="1")
    sol.check("approximate (quadtree) decomposition: the fixed extraction gives a free path", c_quad > 0, f"{c_quad:.3g} m")
    vis = visibility_graph(qs, qg, [diamond])
    sol.value("visibility_length", vis.length, unit="m")
    sol.check_close("visibility graph: shortest path via (5, 5), length 2√(0.5² + 2²)", vis.length,
                    2 * np.hypot(0.5, 2), atol=1e-12, reference="closed form")
    lengths = [float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1))) for p in (fixed, qpath)]
    sol.value("cell_path_lengths", lengths, unit="m")
    sol.check("the cell paths are no shorter than the visibility path", min(lengths) >= vis.length - 1e-12)
    fig, axes = subplots(1, 2, figsize=(11, 5))
    for ax, d, paths, title in [(axes[0], dec, [(naive, "r--", "midpoints only (clearance 0)"),
                                                (fixed, "g-", "with cell centroids (fix)"),
                                                (vis.path, "b:", "visibility graph")], "trapezoidal decomposition"),
                                (axes[1], quad, [(qpath, "g-", "quadtree channel path")], "approximate (quadtree)")]:
        draw_shapes(ax, d.cells, facecolor="none", edgecolor="0.7", lw=0.5)
        draw_shapes(ax, [diamond])
        for k in (chan if d is dec else qchan):
            draw_shapes(ax, [d.cells[k]], facecolor="tab:olive", alpha=0.2, edgecolor="none")
        for p, style, label in paths:
            ax.plot(p[:, 0], p[:, 1], style, marker=".", label=label)
        ax.plot(*qs, "ks", label="q_s")
        ax.plot(*qg, "k^", label="q_g")
        _workspace_axes(ax, (0, 10, 0, 10), title)
        ax.legend(loc="upper right", fontsize=7)
    sol.figure(fig, "Problem 12.6 — channel-to-path extraction")
    return sol


# --------------------------------------------------------------------------------------------
# 12.7–12.8: sampling-based planners
# --------------------------------------------------------------------------------------------

@problem("12.7", "PRM planner for a planar manipulator (2R example)", kind="programming")
def problem_12_7() -> Solution:
    """Write a PRM planner for planar manipulators; plan for a 2R arm from q_s = [−π/4, 3π/4] to
    q_g = [5π/8, −π/2] rad (Fig. S12.3).

    Scene and parameters from the companion file s12_7: links 1 m × 0.1 m, four discs and a square,
    50 vertices (grown further, up to 200, if q_s and q_g are not yet connected: the count at which they
    connect is recorded), ≤ 3 neighbours within C-space distance 3, distance d₃ of Problem 12.2 (C is a
    torus, edges may wrap). The planner accepts an edge only when its own certificate (adaptive bisection
    of the clearance of each robot part against its motion bound) proves it free; the path found is then
    certified again by a second algorithm: re-sampled every 0.05 rad (bisected where inconclusive),
    shape-by-shape clearance of the whole arm against the bound Σ|Δθ_i| R_i on its motion between
    samples. RRT-Connect (+ shortcutting) is the second planner.
    """
    sol = Solution()
    space, qs, qg = scene_12_7()
    sol.given("q_s", qs, unit="rad"), sol.given("q_g", qg, unit="rad")
    given_obstacles(sol, space.scene.obstacles)
    sol.given("link lengths", np.array(space.robot.lengths), unit="m"), sol.given("link width", space.robot.width, unit="m")
    n_vertices, budget = sol.given("n_vertices (companion)", 50), sol.given("max_vertices (growth budget)", 200)
    k_near, d_near = sol.given("max neighbours", 3), sol.given("max neighbour distance", 3.0, unit="rad")
    res = prm(space, qs, qg, np.random.default_rng(SEED), n_vertices=n_vertices, max_neighbors=k_near,
              max_distance=d_near, max_vertices=budget)
    sol.value("message", res.message)
    # the companion's 50 samples do not join q_s and q_g with this seed: the roadmap grows one sample at a time
    # and stops at the first count that does (the companion's own runs are seeded from the clock)
    sol.value("vertices_when_connected", len(res.nodes), unit="1")
    sol.value("certified_by_the_planner", bool(res.certified))
    if not res.success:
        sol.check("PRM joins q_s and q_g within its growth budget", False, res.message)
        return sol
    sol.value("path", res.path, unit="rad")
    sol.value("path_length", res.length, unit="rad")
    sol.value("planner_min_clearance", res.min_clearance, unit="m")
    ok, cmin, n_eval = certify_straight_path(space, res.path, 0.05)
    sol.value("path_min_clearance", cmin, unit="m")
    sol.check("the PRM's path (success and certified by the planner) certified again from q_s to q_g by a second "
              "algorithm: 0.05 rad re-sampling bisected where inconclusive, exact geometry, motion bound Σ|Δθ_i|R_i",
              res.success and res.certified and ok and np.allclose(res.path[[0, -1]], [qs, qg], atol=0),
              f"min clearance {cmin:.4f} m ({n_eval} configurations; the planner's {res.min_clearance:.4f} m)",
              reference="second algorithm")
    sol.check_close("the two certificates find the same smallest clearance along the path [m]", cmin,
                    res.min_clearance, atol=1e-4, reference="second algorithm")
    wrapped = [bool(np.any(np.abs(res.nodes[j] - res.nodes[i]) > np.pi)) for i, j in res.edges]
    sol.value("roadmap_edges", len(res.edges), unit="1")
    sol.value("wrapping_edges", int(sum(wrapped)), unit="1")
    sol.check("C is treated as a torus: some roadmap edges cross q_i = ±π", sum(wrapped) > 0, f"{sum(wrapped)} edges")
    d_seg = torus_distance(res.path[:-1], res.path[1:])
    sol.check_bound("every path edge within the neighbour distance (largest d₃) [rad]", float(d_seg.max()), d_near)
    rc = rrt_connect(space, qs, qg, np.random.default_rng(SEED), step=0.3)
    short = shortcut(space, rc.path, np.random.default_rng(SEED), attempts=200) if rc.success else rc.path
    L_short = path_length(space, short)
    sol.value("rrt_connect_length", rc.length, unit="rad")
    sol.value("rrt_connect_shortcut_length", L_short, unit="rad")
    ok2 = rc.success and certify_straight_path(space, short, 0.05)[0]
    sol.check("RRT-Connect + shortcutting: a path certified by the second algorithm, no longer than before "
              "shortcutting", rc.success and ok2 and L_short <= rc.length + 1e-12, f"{rc.length:.3f} → {L_short:.3f} rad",
              reference="second algorithm")
    fig, axes = subplots(1, 2, figsize=(12, 5.5))
    ax = axes[0]
    draw_shapes(ax, space.scene.obstacles, label="obstacles")
    Q = densify(space, res.path, 0.25)
    for k, q in enumerate(Q):  # stroboscopic
        draw_shapes(ax, space.robot.bodies(q), facecolor=colormaps["viridis"](k / len(Q)), alpha=0.35, lw=0.3)
    ax.plot([], [], "s", color=colormaps["viridis"](0.0), label="start")
    ax.plot([], [], "s", color=colormaps["viridis"](1.0), label="goal")
    _workspace_axes(ax, space.scene.bounds, "stroboscopic motion")
    ax.legend(loc="upper right", fontsize=7)
    ax = axes[1]
    free, _ = _torus_grid(space, 180)
    ax.imshow(~free.T, origin="lower", extent=[-np.pi, np.pi, -np.pi, np.pi], cmap="Greys", alpha=0.5)
    ax.fill([], [], color="0.5", alpha=0.5, label="C-obstacle")      # the map's colour key
    gap = np.full((1, 2), np.nan)  # all edges in one line, split (NaN) at each edge's end and ±π crossing
    parts = []
    for i, j in res.edges:
        seg = densify(space, res.nodes[[i, j]], 0.05)
        jumps = np.flatnonzero(np.any(np.abs(np.diff(seg, axis=0)) > np.pi, axis=1)) + 1
        for part in np.split(seg, jumps):
            parts += [part, gap]
    edges_xy = np.concatenate(parts)
    ax.plot(edges_xy[:, 0], edges_xy[:, 1], color="tab:blue", lw=0.6)
    ax.plot(res.nodes[:, 0], res.nodes[:, 1], ".", color="tab:blue", label="roadmap")
    P = densify(space, res.path, 0.02)
    jumps = np.flatnonzero(np.any(np.abs(np.diff(P, axis=0)) > np.pi, axis=1)) + 1
    for k, part in enumerate(np.split(P, jumps)):
        ax.plot(part[:, 0], part[:, 1], color="0.3", lw=3, label="solution path" if k == 0 else None)
    ax.plot(*qs, "gs", label="q_s")
    ax.plot(*qg, "r^", label="q_g")
    _cspace_axes(ax, "PRM in C (a torus; C-obstacles shaded)")
    ax.legend(loc="upper right", fontsize=7)
    sol.figure(fig, "Fig. S12.3 — PRM for a 2R planar manipulator")
    from rigid_body.robots import load  # the book's 2R arm: the same links (1 m, 1 m), drawn by the viewer
    Q = np.unwrap(densify(space, res.path, 0.02), axis=0)  # continuous angles: no 2π spin when playing it
    tip = lambda Qs: np.array([space.robot.joint_positions(q)[-1] for q in Qs])  # noqa: E731
    roadmap = [tip(densify(space, res.nodes[[i, j]], 0.1)) for i, j in res.edges]  # edges traced by the tip
    sol.animation(load("planar_2r"), (np.r_[0.0, np.cumsum(torus_distance(Q[:-1], Q[1:]))], Q),
                  "the arm along the PRM path at 1 rad/s (blue: the roadmap's edges traced by the tip)", fps=25,
                  overlays=lambda s: (s.planar_shapes("obstacles", space.scene.obstacles, 0.2, "#d62728"),
                                      s.polyline("roadmap", roadmap, "#1f77b4"),
                                      s.polyline("tip_path", tip(Q[::5]), "#2ca02c", radius=0.012)))
    return sol


def _arc_samples(q: np.ndarray, v: float, omega: float, delta: float, h: float) -> np.ndarray:
    n = max(int(np.ceil(delta / h)), 1)
    return unicycle_arc(q, v, omega, np.linspace(0.0, delta, n + 1))


def lattice_primitives(step: float, delta: float) -> list[MotionPrimitive]:
    """Lattice primitives for the unicycle: a straight move of length ``step`` and left/right quarter turns of
    radius ``step``, each over ``delta`` s. From a start with θ = 0 the reachable configurations form a lattice:
    positions q_s + step·(i, j), headings multiples of π/2 — so a goal near a lattice point is reached up to
    the lattice's offset from it, exactly (a state lattice)."""
    return [MotionPrimitive(step / delta, 0.0), MotionPrimitive(np.pi / 2 * step / delta, np.pi / 2 / delta),
            MotionPrimitive(np.pi / 2 * step / delta, -np.pi / 2 / delta)]


def closest_primitive_sequence(q_start: np.ndarray, q_goal: np.ndarray, primitives: list[MotionPrimitive],
                               delta: float, depth: int, threshold: float) -> tuple[float, int]:
    """Branch and bound over every sequence of at most ``depth`` primitives from q_start, obstacles ignored:
    (the smallest R² × SO(2) distance to q_goal found, the sequences examined). A partial sequence is dropped
    once it can no longer end within ``threshold`` of q_goal in the steps left (each moves the reference point
    by at most |v|Δ and turns it by at most |ω|Δ); so no sequence of at most ``depth`` primitives ends within
    ``threshold`` unless the distance returned is below it. A lower bound for any tree of primitive arcs,
    whatever its samples (obstacles only remove branches)."""
    reach, turn = max(abs(p.v) for p in primitives) * delta, max(abs(p.omega) for p in primitives) * delta

    def arcs(Q: np.ndarray, v: float, w: float) -> np.ndarray:
        """The exact motions (11.85) of the configurations Q (N, 3) under (v, ω) for Δ (written here, vectorised)."""
        th = Q[:, 2]
        if w == 0.0:
            return np.column_stack([Q[:, 0] + v * delta * np.cos(th), Q[:, 1] + v * delta * np.sin(th), th])
        th1 = th + w * delta
        return np.column_stack([Q[:, 0] + v / w * (np.sin(th1) - np.sin(th)), Q[:, 1] - v / w * (np.cos(th1) - np.cos(th)),
                                np.angle(np.exp(1j * th1))])

    Q = np.asarray(q_start, dtype=float)[None]
    best, examined = np.inf, 0
    for d in range(1, depth + 1):
        Q = np.vstack([arcs(Q, p.v, p.omega) for p in primitives])
        examined += len(Q)
        left = depth - d
        miss = np.hypot(*(Q[:, :2] - q_goal[:2]).T)
        heading = np.abs(np.angle(np.exp(1j * (Q[:, 2] - q_goal[2]))))
        best = min(best, float(np.sqrt(miss ** 2 + heading ** 2).min()))
        Q = Q[(miss <= left * reach + threshold) & (heading <= left * turn + threshold)]
        if not len(Q):
            break
    return best, examined


@problem("12.8", "RRT for a unicycle with motion primitives", kind="programming")
def problem_12_8() -> Solution:
    """Write an RRT planner for the unicycle using motion primitives; plan from q_s = [−3, 0, 0] to
    q_g = [3, −3.5, 0] [m, m, rad] (Fig. S12.4).

    Companion data (s12_8): triangular robot, four discs and three squares, primitives (v, ω) = (1, 0),
    (1, ±1.3) held for Δ = 0.9 s, 200 vertices, goal threshold 0.01, goal bias 0.2. The manual's program stops
    when a vertex is within the threshold of q_g. With these primitives it cannot: every turn changes the
    heading by 1.17 rad, so only sequences with as many left as right turns end near θ = 0, and their end
    points are sparse — a branch and bound over all the sequences of up to 16 primitives (twice the straight
    distance; obstacles ignored, so a bound for any tree) finds none within the threshold (the closest 0.0115);
    the 200-vertex tree stops 0.24 away (the manual's figure also shows the robot short of q_g). The run that terminates within
    the threshold uses lattice primitives (:func:`lattice_primitives`: a 0.5004 m straight and quarter turns of
    that radius over Δ = 0.5 s), whose reachable configurations include q_s + (12, −7)·0.5004 m, 5.6 mm from
    q_g, under a stated budget of 2000 vertices. Arcs are the unicycle's exact closed-form motion (checked
    against scipy's RK45 integration of the model); the path is certified collision-free along the arcs.
    """
    from scipy.integrate import solve_ivp

    sol = Solution()
    space, qs, qg = scene_12_8()
    sol.given("q_s", qs, unit="m, m, rad"), sol.given("q_g", qg, unit="m, m, rad")
    given_obstacles(sol, space.scene.obstacles)
    given_obstacles(sol, space.robot.parts, "robot body")
    threshold, bias = sol.given("goal threshold", 0.01), sol.given("goal bias", 0.2)
    companion = [MotionPrimitive(1.0, 0.0), MotionPrimitive(1.0, 1.3), MotionPrimitive(1.0, -1.3)]
    sol.given("companion primitives (v, ω)", np.array([[1.0, 0.0], [1.0, 1.3], [1.0, -1.3]]), unit="m/s, rad/s")
    delta_c = sol.given("companion Δ", 0.9, unit="s")
    vertices_c = sol.given("companion max_vertices", 200)
    step, delta = sol.given("lattice step", 0.5004, unit="m"), sol.given("lattice Δ", 0.5, unit="s")
    budget = sol.given("lattice run budget (max_vertices)", 2000)

    # the companion's primitives: the tree stops at its 200 vertices short of the threshold, and no tree could do
    # better at that depth
    short = unicycle_rrt(space, qs, qg, np.random.default_rng(SEED), companion, delta_c, max_vertices=vertices_c,
                         goal_threshold=threshold, goal_bias=bias)
    d_short = float(space.distance(short.path[-1], qg))
    sol.value("companion_run", short.message)
    sol.value("companion_final_distance", d_short, unit="m | rad (Euclidean in (x, y, θ))")
    depth = 16
    bound_16, examined = closest_primitive_sequence(qs, qg, companion, delta_c, depth, threshold)
    bound_path, _ = closest_primitive_sequence(qs, qg, companion, delta_c, len(short.path) - 1, threshold)
    sol.value("companion_closest_over_16_primitives", bound_16, unit="m | rad (Euclidean in (x, y, θ))")
    sol.check_bound(f"why the companion's run cannot terminate: no sequence of ≤ {depth} of its primitives (obstacles "
                    f"ignored; {examined} partial sequences examined) ends within the threshold of q_g — the closest",
                    bound_16, threshold, ">", reference="second algorithm")
    sol.check_bound(f"the companion's tree (its path of {len(short.path) - 1} arcs ends {d_short:.3f} from q_g) is no "
                    "closer than the best of all sequences of that many primitives", d_short, bound_path - 1e-12, ">=",
                    reference="second algorithm", detail=f"{d_short:.4g} ≥ {bound_path:.4g}")

    prims = lattice_primitives(step, delta)
    res = unicycle_rrt(space, qs, qg, np.random.default_rng(SEED), prims, delta, max_vertices=budget,
                       goal_threshold=threshold, goal_bias=bias)
    d_end = float(space.distance(res.path[-1], qg))
    sol.value("message", res.message)
    sol.value("vertices", len(res.nodes), unit="1")
    sol.value("path", res.path, unit="m, m, rad")
    sol.value("controls", res.controls, unit="m/s, rad/s")
    sol.value("final_distance_to_goal", d_end, unit="m | rad (Euclidean in (x, y, θ))")
    sol.value("final_position_error", float(np.linalg.norm(res.path[-1][:2] - qg[:2])), unit="m")
    sol.value("path_length_workspace", float(np.sum(np.abs(res.controls[:, 0])) * delta), unit="m")
    sol.check_bound(f"lattice primitives: the tree reaches q_g within the threshold (success, {len(res.nodes)} vertices "
                    f"of the budget {budget})", d_end if res.success else np.inf, threshold)
    d_all = space.distance(res.nodes, qg)
    sol.check("the search stops at the first vertex within the threshold (the manual's program): every other vertex "
              "is farther", res.success and int(np.argmin(d_all)) == len(res.nodes) - 1
              and bool(np.all(d_all[:-1] > threshold)), res.message)
    lattice_point = qs + np.r_[np.round((qg - qs)[:2] / step) * step, 0.0]
    sol.check_close("… at the lattice point q_s + step·round((q_g − q_s)/step): its offset from q_g, "
                    "‖(12, −7)·(0.5004 − 0.5)‖ m", d_end, float(space.distance(lattice_point, qg)), atol=1e-9,
                    reference="closed form")

    def unicycle(t, x, v, w):
        return [v * np.cos(x[2]), v * np.sin(x[2]), w]

    replay = np.asarray(qs, float)
    for v, w in res.controls:          # the whole control sequence applied from q_s (SciPy's RK45)
        replay = solve_ivp(unicycle, (0, delta), replay, args=(v, w), method="RK45", rtol=1e-11, atol=1e-12).y[:, -1]
    sol.check_error("the controls applied from q_s (RK45 on the model) end at the path's last vertex",
                    float(np.max(np.abs(space.difference(replay, res.path[-1])))), 1e-7, reference="other library")

    err = max_error((space.difference(solve_ivp(unicycle, (0, delta), a, args=(v, w), method="RK45", rtol=1e-11,
                                                atol=1e-12).y[:, -1], b), 0.0)
                    for a, b, (v, w) in zip(res.path[:-1], res.path[1:], res.controls))
    sol.value("max_edge_error_vs_rk45", err, unit="m or rad (the largest of x, y, θ)")
    sol.check_error("every edge is its primitive over Δ: closed-form arc (exact integration (11.85)) = RK45 on the model",
                    err, 1e-8, reference="other library")
    # a second certificate along the arcs: the whole body's clearance (exact geometry) every 10 ms, against the
    # bound (|v| + |ω| r) τ on how far any point of the body moves in τ (r its radius about the reference point);
    # an inconclusive interval is re-sampled 50 times finer
    r_body = space.robot.radius()
    S, ok, worst = [qs[None]], True, np.inf
    for a, (v, w) in zip(res.path[:-1], res.controls):
        rate = abs(v) + abs(w) * r_body
        arc = _arc_samples(a, v, w, delta, 0.01)
        tau = delta / (len(arc) - 1)
        c = space.clearance(arc)
        worst = min(worst, float(c.min()))
        for k in np.flatnonzero(c[:-1] + c[1:] <= rate * tau):
            cf = space.clearance(unicycle_arc(a, v, w, np.linspace(k, k + 1, 51) * tau))
            worst = min(worst, float(cf.min()))
            ok &= bool(np.all(cf[:-1] + cf[1:] > rate * tau / 50))
        S.append(arc[1:])
    S = np.vstack(S)
    sol.value("path_min_clearance", worst, unit="m")
    sol.check("path (certified by the planner) certified again along the arcs by a second algorithm: 10 ms samples "
              "(0.2 ms where inconclusive), exact geometry, motion bound (|v| + |ω| r) τ", res.certified and ok,
              f"min clearance {worst:.4f} m (the planner's {res.min_clearance:.4f} m)", reference="second algorithm")
    fig = Figure(figsize=(12, 5.5))
    ax = fig.add_subplot(1, 2, 1)
    draw_shapes(ax, space.scene.obstacles, label="obstacles")
    tree = []  # the tree's arcs in the plane (also drawn in the animation)
    for i, j in res.edges:
        k = j  # child vertex: find the primitive that created it
        arc = None
        for p in prims:
            cand = unicycle_arc(res.nodes[i], p.v, p.omega, delta)
            if np.allclose(space.difference(cand, res.nodes[k]), 0, atol=1e-9):
                arc = _arc_samples(res.nodes[i], p.v, p.omega, delta, 0.05)
                break
        if arc is not None:
            ax.plot(arc[:, 0], arc[:, 1], color="tab:blue", lw=0.5)
            tree.append(arc[:, :2])
    ax.plot([], [], color="tab:blue", lw=0.5, label="RRT (projection)")
    for q in S[:: max(len(S) // 25, 1)]:
        draw_shapes(ax, space.robot.bodies(q), facecolor="tab:orange", alpha=0.5, lw=0.3)
    ax.plot(S[:, 0], S[:, 1], "k", lw=1.5, label="solution path")
    draw_shapes(ax, space.robot.bodies(qg), facecolor="0.85", alpha=0.9, lw=0.5)
    ax.plot(*qg[:2], "r^", label="q_g")
    _workspace_axes(ax, (-4.5, 4.5, -4.5, 3), "stroboscopic motion and the tree")
    ax.legend(loc="upper right", fontsize=7)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    ax.scatter(res.nodes[:, 0], res.nodes[:, 1], res.nodes[:, 2], s=3, color="tab:blue", label="RRT vertices")
    ax.plot(S[:, 0], S[:, 1], np.where(np.abs(np.diff(S[:, 2], prepend=S[0, 2])) > np.pi, np.nan, S[:, 2]),
            color="0.3", lw=2.5, label="solution path")
    ax.scatter(*qg, color="r", marker="^", label="q_g")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("θ [rad]")
    ax.set_title("RRT in R² × SO(2)")
    ax.legend(loc="upper left", fontsize=7)
    fig.subplots_adjust(left=0.06, right=0.97, bottom=0.1, top=0.88, wspace=0.12)   # (a 3-D panel: no tight layout)
    sol.figure(fig, "Fig. S12.4 — RRT with lattice motion primitives for a unicycle", tight=False)
    from viewer.mobile import planar_body, plane_camera
    # the triangle (−0.1…0.5) × (−0.2…0.2) m as a box; |v| = 1 m/s: time = distance travelled
    S_unwrapped = np.c_[S[:, :2], np.unwrap(S[:, 2])]
    sol.animation(planar_body(0.6, 0.4, name="unicycle", offset=0.2), (np.r_[0.0, np.cumsum(np.linalg.norm(
                  np.diff(S[:, :2], axis=0), axis=1))], S_unwrapped), "the unicycle along the RRT path (blue: the "
                  "tree's arcs, red cone: q_g)", fps=25, camera=plane_camera([[-4.5, -4.5], [4.5, 3.0]], 0.0),
                  overlays=lambda s: (s.planar_shapes("obstacles", space.scene.obstacles, 0.3, "#7f7f7f"),
                                      s.polyline("tree", tree, "#1f77b4"),
                                      s.polyline("path", S[::20, :2], "#2ca02c", radius=0.02),
                                      s.arrow("goal", [*qg[:2], 0.05], [0.5 * np.cos(qg[2]), 0.5 * np.sin(qg[2]), 0.0],
                                              "#d62728", 0.03)))
    return sol


# --------------------------------------------------------------------------------------------
# 12.9–12.13: artificial potentials and navigation functions
# --------------------------------------------------------------------------------------------

@problem("12.9", "Paraboloid + cone attractive potential: continuity of the force at ρ", kind="derivation")
def problem_12_9() -> Solution:
    """Combine the paraboloidal (‖e‖ ≤ ρ) and conical (‖e‖ > ρ) attractive potentials so that the
    attractive force is continuous; give k_b.

    Solved symbolically (sympy): k_a ρ = k_b, i.e. k_b = ρ k_a (manual). Checked numerically across the
    sphere ‖e‖ = ρ in random directions. Note: as written (k_b‖e‖ outside) U jumps by ½k_aρ² at ρ; the
    library uses k_b‖e‖ − ½k_aρ² outside, continuous, with the same force.
    """
    import sympy as sp

    sol = Solution()
    k_a, k_b, rho = sp.symbols("k_a k_b rho", positive=True)
    e = sp.symbols("e", positive=True)   # ‖e‖
    f_in = sp.diff(sp.Rational(1, 2) * k_a * e ** 2, e)
    f_out = sp.diff(k_b * e, e)
    k_b_sol = sp.solve(sp.Eq(f_in.subs(e, rho), f_out.subs(e, rho)), k_b)
    sol.value("k_b", str(k_b_sol[0]))
    sol.check("sympy: force magnitudes equal at ‖e‖ = ρ ⟺ k_b = ρ k_a (manual)", len(k_b_sol) == 1
              and sp.simplify(k_b_sol[0] - rho * k_a) == 0, str(k_b_sol), reference="closed form")
    jump = sp.simplify((k_b * e).subs({k_b: rho * k_a, e: rho}) - (sp.Rational(1, 2) * k_a * e ** 2).subs(e, rho))
    sol.value("potential_jump_without_offset", str(jump))
    att = AttractivePotential(sol.given("goal (test value)", np.array([1.0, -2.0]), unit="m"),
                              k_a=sol.given("k_a (test value)", 2.0), rho=sol.given("ρ (test value)", 0.7, unit="m"))
    rng = np.random.default_rng(SEED)
    u = rng.normal(size=(200, 2))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    eps = 1e-9
    q_in, q_out = att.goal - (att.rho - eps) * u, att.goal - (att.rho + eps) * u
    sol.check_error("force continuous across ‖e‖ = ρ (200 directions)",
                    max_error([(att.force(q_in), att.force(q_out))]), 1e-7, reference="closed form")
    sol.check_error("potential continuous with the offset −½k_aρ²",
                    max_error([(att.potential(q_in), att.potential(q_out))]), 1e-7, reference="closed form")
    sol.value("potential_jump_without_offset_here", float(jump.subs({k_a: att.k_a, rho: att.rho})), unit="J")
    qs = att.goal - np.linspace(0, 2, 401)[:, None] * u[0]
    h = 1e-6
    fd = np.array([-(att.potential(qs + d) - att.potential(qs - d)) / (2 * h) for d in np.eye(2) * h]).T
    good = np.abs(np.linalg.norm(qs - att.goal, axis=1) - att.rho) > 1e-4
    good &= np.linalg.norm(qs - att.goal, axis=1) > 1e-4
    sol.check_close("force = −∇U (finite differences, both regions)", att.force(qs[good]), fd[good], atol=1e-6,
                    reference="finite differences")
    fig, axes = subplots(1, 2, figsize=(10, 3.8))
    r = np.linspace(0, 2, 401)
    q_line = att.goal - r[:, None] * u[0]
    axes[0].plot(r, att.potential(q_line), label="U_a (combined, continuous)")
    axes[0].plot(r, 0.5 * att.k_a * r ** 2, "--", label="paraboloid ½k_a‖e‖²")
    axes[0].plot(r, att.k_b * r, ":", label="cone k_b‖e‖ (manual)")
    axes[1].plot(r, np.linalg.norm(att.force(q_line), axis=1), label="‖f_a‖")
    for ax in axes:
        ax.axvline(att.rho, color="0.6", lw=0.8, label="ρ")
        ax.set_xlabel("‖e‖ [m]")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("U_a [J]")
    axes[1].set_ylabel("‖f_a‖ [N]")
    sol.figure(fig, f"Problem 12.9 — k_a = {att.k_a}, ρ = {att.rho} m, k_b = ρk_a = {att.k_b:.2f}")
    return sol


def _disc_field(centers, radius=0.5, k_a=1.0, k_r=1.0, eta0=1.0) -> PotentialField:
    return PotentialField(AttractivePotential([0.0, 0.0], k_a),
                          tuple(RepulsivePotential(Disc(c, radius), k_r, eta0) for c in centers))


def _hessian_closed_form(q, centers, radius, k_a, k_r, eta0) -> np.ndarray:
    """∇²U at q for the paraboloid + discs (γ = 2), in closed form: with U_r = φ(η), η = ‖q − c‖ − ρ,
    ∇²U_r = φ''(η) n nᵀ + φ'(η)(I − n nᵀ)/‖q − c‖; φ' = −k_r(1/η − 1/η₀)/η², φ'' = k_r/η⁴ + 2k_r(1/η − 1/η₀)/η³."""
    H = k_a * np.eye(2)
    for c in centers:
        d = np.asarray(q) - c
        r = np.linalg.norm(d)
        eta = r - radius
        if eta > eta0:
            continue
        n = d / r
        p1 = -k_r * (1 / eta - 1 / eta0) / eta ** 2
        p2 = k_r / eta ** 4 + 2 * k_r * (1 / eta - 1 / eta0) / eta ** 3
        H += p2 * np.outer(n, n) + p1 * (np.eye(2) - np.outer(n, n)) / r
    return H


@problem("12.10", "Attractive + repulsive potentials create local minima (and saddles)", kind="derivation")
def problem_12_10() -> Solution:
    """Show that superposing attractive and repulsive potentials can create local minima.

    Manual: on the half-line from q_g through the obstacle centre U → ∞ at both ends, so ∇U = 0 at some
    P, "a local minimum also in the direction AB". **Erratum:** for a circular obstacle that transversal
    argument is wrong and P is a saddle: goal at the origin, disc (3, 0) radius 0.5, k_a = k_r = η₀ = 1
    gives P = (4, 0) with Hessian eigenvalues −3 (tangential, −k_a D/(ρ + η)) and +33. True local
    minima need several (or non-convex) obstacles: discs at (3, ±0.8) give a minimum at ≈ (3.669, 0),
    U ≈ 7.4399, where gradient descent from (3.67, 0.05) stops instead of reaching the goal (Fig. S12.5).
    """
    sol = Solution()
    sol.given("disc centre", np.array([3.0, 0.0]), unit="m")
    sol.given("ρ, k_a, k_r, η₀", np.array([0.5, 1.0, 1.0, 1.0]))
    single = _disc_field([[3.0, 0.0]])
    P = stationary_point(single, [3.9, 0.1])
    sol.value("P_single", P, unit="m")
    sol.check_close("single disc: ∇U(P) = 0 on the goal–centre axis, at (4, 0) (η = 0.5)", P, [4.0, 0.0], atol=1e-9,
                    reference="closed form")
    H = single.hessian(P)
    H_cf = _hessian_closed_form(P, [[3.0, 0.0]], 0.5, 1.0, 1.0, 1.0)
    sol.check_close("Hessian: finite differences of the force = closed form", H, H_cf, atol=1e-5,
                    reference="finite differences")
    ev = np.linalg.eigvalsh(H_cf)
    sol.value("eig_single", ev, unit="N/m")
    sol.check_close("eigenvalues −k_a D/(ρ + η) = −3 (tangential) and +33 (radial)", ev, [-3.0, 33.0], atol=1e-9,
                    reference="closed form")
    sol.check("erratum: the single-disc stationary point is a saddle (indefinite Hessian), not a minimum",
              ev[0] < 0 < ev[1])
    double = _disc_field(sol.given("two disc centres", np.array([[3.0, 0.8], [3.0, -0.8]]), unit="m"))
    M = stationary_point(double, [3.67, 0.02])
    U_M = float(double.potential(M))
    ev2 = np.linalg.eigvalsh(_hessian_closed_form(M, [[3.0, 0.8], [3.0, -0.8]], 0.5, 1.0, 1.0, 1.0))
    sol.value("minimum_two_discs", M, unit="m")
    sol.value("U_minimum", U_M, unit="J")
    sol.value("eig_two_discs", ev2, unit="N/m")
    sol.check_close("two discs: stationary point ≈ (3.669, 0), U ≈ 7.4399", [M[0], M[1], U_M],
                    [3.669, 0.0, 7.4399], atol=1e-3, reference="independent derivation")
    sol.check("two discs: positive-definite Hessian ⇒ a true local minimum", ev2[0] > 0, f"{ev2}")
    run = gradient_descent(double.force, [3.67, 0.05], step=0.01, tol=1e-8)
    sol.check("gradient descent from (3.67, 0.05) is trapped there, not at the goal",
              run.converged and np.linalg.norm(run.path[-1] - M) < 1e-6 and np.linalg.norm(run.path[-1]) > 3,
              run.message)
    fig, axes = subplots(1, 2, figsize=(11, 4.8))
    X, Y = np.meshgrid(np.linspace(1, 5.5, 300), np.linspace(-2, 2, 260))
    for ax, field, pts, title, centers in [
            (axes[0], single, [(P, "rx", "saddle P")], "one disc: P is a saddle", [[3, 0]]),
            (axes[1], double, [(M, "g*", "local minimum")], "two discs: a true local minimum", [[3, 0.8], [3, -0.8]])]:
        U = field.potential(np.stack([X, Y], -1))
        ax.contour(X, Y, np.minimum(U, 12), levels=40, linewidths=0.6)
        draw_shapes(ax, [Disc(c, 0.5) for c in centers])
        for p, style, label in pts:
            ax.plot(*p, style, ms=10, label=label)
        if field is double:
            ax.plot(run.path[:, 0], run.path[:, 1], "k.-", ms=2, label="gradient descent")
        ax.plot([1, 5.5], [0, 0], "k:", lw=0.6, label="half-line from q_g through the centre")
        _workspace_axes(ax, (1, 5.5, -2, 2), title)
        ax.legend(loc="upper left", fontsize=7)
    sol.figure(fig, "Fig. S12.5 — stationary points of U = U_a + U_r (goal at the origin)")
    return sol


@problem("12.11", "Potential field with three circular obstacles: the saddle points", kind="derivation")
def problem_12_11() -> Solution:
    """Point robot, goal at the origin, three circular obstacles: write U_t and f_t and locate the
    saddle points.

    Data (defined here, the textbook's values are not given): centres (3, 0), (0, 4), (−3, −3), radii
    0.5, k_a = k_r = 1, η₀ = 1, γ = 2. With non-overlapping ranges of influence each saddle lies on the
    ray from the goal through C_i, beyond the obstacle, where f_a + f_{r,i} = 0:
    k_a(D_i + ρ_i + η) = (k_r/η²)(1/η − 1/η₀) (solved by brentq) — and checked as zeros of the full 2-D
    force (scipy root). **Sign erratum:** the manual's balance −k_a[x y]ᵀ = (k_r/η²)(…)∇η has no solution
    there (both sides point in opposite directions); the correct balance is k_a[x y]ᵀ = (k_r/η²)(…)∇η.
    """
    from scipy.optimize import brentq

    sol = Solution()
    centers = sol.given("centres", np.array([[3.0, 0.0], [0.0, 4.0], [-3.0, -3.0]]), unit="m")
    rho, k_a, k_r, eta0 = 0.5, 1.0, 1.0, 1.0
    sol.given("ρ, k_a, k_r, η₀", np.array([rho, k_a, k_r, eta0]))
    field = _disc_field(centers, rho, k_a, k_r, eta0)
    saddles, residual_manual = [], []
    for c in centers:
        D = np.linalg.norm(c)
        g = lambda eta: k_a * (D + rho + eta) - k_r / eta ** 2 * (1 / eta - 1 / eta0)  # noqa: E731
        eta = brentq(g, 1e-3, eta0)
        q = c / D * (D + rho + eta)
        saddles.append(q)
        manual = lambda eta: -k_a * (D + rho + eta) - k_r / eta ** 2 * (1 / eta - 1 / eta0)  # noqa: E731
        etas = np.linspace(1e-3, eta0, 2000)
        residual_manual.append(bool(np.all(manual(etas) < 0)))
    saddles = np.array(saddles)
    sol.value("saddles", saddles, unit="m")
    f_norm = np.linalg.norm(field.force(saddles), axis=1)
    sol.check_error("the library's f_t vanishes at the three points of the scalar balance (the other obstacles out of "
                    "range) [N]", f_norm.max(), 1e-9, reference="closed form")
    roots = np.array([stationary_point(field, q + [0.05, -0.05]) for q in saddles])
    sol.check_close("2-D root finder on f_t (from perturbed seeds) finds the same points", roots, saddles, atol=1e-9,
                    reference="second algorithm")
    eig = np.array([np.linalg.eigvalsh(_hessian_closed_form(q, centers, rho, k_a, k_r, eta0)) for q in saddles])
    sol.value("hessian_eigenvalues", eig, unit="N/m")
    sol.check("each is a saddle: one negative, one positive Hessian eigenvalue", np.all((eig[:, 0] < 0) & (eig[:, 1] > 0)))
    sol.check_error("the 2-D roots (found off the rays) lie on the rays from the goal through the centres: max "
                    "|roots × c_i| / ‖c_i‖ [m]", float(np.max(np.abs(np.cross(roots, centers)) / np.linalg.norm(centers,
                                                                                                               axis=1))),
                    1e-9, reference="second algorithm")
    sol.check_bound("… beyond the obstacles, in their shadow (smallest ‖root‖ − ‖c_i‖ − ρ) [m]",
                    float(np.min(np.linalg.norm(roots, axis=1) - np.linalg.norm(centers, axis=1) - rho)), 0.0, ">")
    sol.check("sign erratum: the manual's balance −k_a q = (k_r/η²)(1/η − 1/η₀)∇η has no root on the ray",
              all(residual_manual))
    rng = np.random.default_rng(SEED)
    Q = rng.uniform(-5, 5, (400, 2))
    eta_all = np.linalg.norm(Q[:, None] - centers[None], axis=-1) - rho
    Q = Q[np.all(eta_all > 0.1, axis=1)]
    h = 1e-6
    fd = np.array([-(field.potential(Q + d) - field.potential(Q - d)) / (2 * h) for d in np.eye(2) * h]).T
    sol.check_close(f"analytic f_t = −∇U_t (finite differences, {len(Q)} random points)", field.force(Q), fd,
                    atol=1e-4, rtol=1e-6, reference="finite differences")
    fig, ax = subplots(figsize=(6.5, 6))
    X, Y = np.meshgrid(np.linspace(-5, 5, 300), np.linspace(-5, 6, 330))
    U = field.potential(np.stack([X, Y], -1))
    ax.contour(X, Y, np.minimum(U, 25), levels=50, linewidths=0.5)
    draw_shapes(ax, [Disc(c, rho) for c in centers], label="obstacles")
    ax.plot(saddles[:, 0], saddles[:, 1], "rx", ms=10, label="saddle points")
    return _potential_figure(sol, fig, ax, (0, 0), (-5, 5, -5, 6), "Problem 12.11 — U_t and its saddle points",
                             "lower right")


def _reactive_comparison(obstacles: list, goal: np.ndarray, R: float, n_rays: int, k_a: float, k_r: float,
                         eta0: float, radius: float, points: np.ndarray) -> dict:
    """Problem 12.12 for a robot of ``radius`` (0: a point): the off-line field (the exact distances η_i of the
    obstacles, minus the radius) against the reactive one (η_i, ∇η_i from a 720-ray scan of range R, minus the
    radius), at the test ``points`` with an obstacle within η₀ and in closed loop q_{k+1} = q_k + T f(q_k)."""
    att = AttractivePotential(goal, k_a, rho=1.0)

    def offline_repulsion(q: np.ndarray) -> np.ndarray:
        f = np.zeros(2)
        for o in obstacles:
            eta, grad = RepulsivePotential(o).eta(q)
            f += float(repulsive_magnitude(float(eta) - radius, k_r, eta0)) * np.asarray(grad).reshape(2)
        return f

    def reactive_repulsion(q: np.ndarray) -> np.ndarray:
        angles, ranges = range_scan(q, obstacles, n_rays, R)
        return reactive_repulsive_force(q, scan_segments(q, angles, ranges), k_r, eta0, robot_radius=radius)

    d_alpha = 2 * np.pi / n_rays
    F = lambda eta: k_r / eta ** 2 * (1 / eta - 1 / eta0)                       # (12.15), γ = 2  # noqa: E731
    dF = lambda eta: k_r * (3 / eta ** 4 - 2 / (eta ** 3 * eta0))               # |dF/dη|  # noqa: E731
    rel, ratio = [], []
    for q in points:
        f_off, f_re = offline_repulsion(q), reactive_repulsion(q)
        centre = np.array([float(RepulsivePotential(o).eta(q)[0]) for o in obstacles])
        near = centre - radius <= eta0
        # first-order resolution bound: the closest point is missed by ≤ η Δα sideways (so η − ρ by ≤ η Δα) and
        # the direction by ≤ Δα, η the distance from the robot's centre
        bound = float(np.sum(dF(centre[near] - radius) * centre[near] * d_alpha + F(centre[near] - radius) * d_alpha))
        err = float(np.linalg.norm(f_re - f_off))
        rel.append(err / max(np.linalg.norm(f_off), 1e-12))
        ratio.append(err / bound)
    q0 = np.array([0.0, 0.8])
    runs = [gradient_descent(lambda q, rep=rep: att.force(q) + rep(q), q0, step=0.02, tol=1e-3, max_iterations=3000,
                             max_move=0.05, obstacles=shapes, robot_radius=radius)
            for rep, shapes in ((offline_repulsion, None), (reactive_repulsion, obstacles))]   # the reactive one certified
    return dict(rel=np.array(rel), ratio=np.array(ratio), offline=runs[0], reactive=runs[1])


@problem("12.12", "Reactive potential-field planning from laser range data", kind="derivation")
def problem_12_12() -> Solution:
    """Explain how to plan on line with artificial potentials from a rotating laser range finder.

    The attractive term is the off-line one; the repulsive forces (12.15) use η_i and ∇η_i read from the
    scan, one per perceived (convex) obstacle, with η₀ ≤ R; a disc robot of radius ρ uses η_i − ρ (and
    η₀ ≤ R − ρ, so that what is within η₀ of its rim is within the scanner's range). Scene defined here: three
    convex polygons and a 720-ray scanner of range R = 3 m; a point robot (η₀ = R) and a disc robot of radius
    0.2 m (η₀ = R − ρ). Checks, for each: the reactive repulsive force matches the exact off-line one within
    2 % (angular resolution) wherever an obstacle is within η₀, and within a first-order resolution bound
    everywhere; the two closed-loop motions q_{k+1} = q_k + T f(q_k) coincide within 1 cm, reach the goal and
    are certified collision-free for the robot's size (Fig. S12.6).
    """
    sol = Solution()
    R, n_rays = sol.given("R (laser range)", 3.0, unit="m"), sol.given("rays", 720)
    obstacles = [Polygon([[2, 1.0], [3.2, 0.6], [3.5, 2.0], [2.4, 2.3]]),
                 Polygon([[4.5, -2.2], [6.0, -1.8], [5.6, -0.6], [4.4, -0.9]]),
                 Polygon([[7.0, 1.2], [8.3, 1.0], [8.0, 2.6]])]
    for k, o in enumerate(obstacles, start=1):
        sol.given(f"obstacle {k}", o.vertices, unit="m")
    goal = sol.given("goal", np.array([12.0, 0.5]), unit="m")
    k_a, k_r = sol.given("k_a, k_r", np.array([1.0, 0.5]))
    radius = sol.given("disc robot radius ρ", 0.2, unit="m")

    rng = np.random.default_rng(SEED)
    pts = rng.uniform([0, -3], [10, 3], (300, 2))
    results = {}
    for label, rho, eta0 in (("point robot", 0.0, R), ("disc robot", radius, R - radius)):
        d = np.array([[float(RepulsivePotential(o).eta(q)[0]) for o in obstacles] for q in pts]).min(axis=1)
        keep = pts[(d - rho > 0.3) & (d - rho < eta0)]
        r = results[label] = _reactive_comparison(obstacles, goal, R, n_rays, k_a, k_r, eta0, rho, keep)
        rel, ratio, run_off, run_re = r["rel"], r["ratio"], r["offline"], r["reactive"]
        key = "" if rho == 0 else "disc_"                         # (the point robot's values keep their names)
        sol.value(f"{key}relative_force_error_median", float(np.median(rel)), unit="1")
        sol.value(f"{key}relative_force_error_max", float(rel.max()), unit="1")
        sol.check_bound(f"{label}: reactive repulsive force within 2 % of the off-line force (exact distances) at 90 % "
                        f"of {len(keep)} positions within η₀ = {eta0:g} m (90th percentile of the relative error)",
                        float(np.quantile(rel, 0.9)), 0.02, reference="second algorithm",
                        detail=f"median {np.median(rel):.2%}, max {rel.max():.2%}")
        sol.check_bound(f"{label}: everywhere within the angular-resolution bound Σ(|F'(η − ρ)|η + F(η − ρ))Δα, "
                        "Δα = 2π/720 (largest error/bound)", float(ratio.max()), 1.0, reference="closed form")
        # the two polylines compared as curves (symmetric Hausdorff distance of their 1 mm re-samplings, scipy):
        # matching iterates by index would count a one-step lag along the same curve as a deviation
        dense = [np.vstack([np.linspace(a, b, max(int(np.ceil(np.linalg.norm(b - a) / 1e-3)), 1), endpoint=False)
                            for a, b in zip(run.path[:-1], run.path[1:])] + [run.path[-1:]]) for run in (run_off, run_re)]
        dev = float(max(directed_hausdorff(dense[0], dense[1])[0], directed_hausdorff(dense[1], dense[0])[0]))
        sol.value(f"{key}trajectory_max_deviation", dev, unit="m")
        sol.value(f"{key}final_position_reactive", run_re.path[-1], unit="m")
        sol.check_bound(f"{label}: both planners reach the goal (the reactive one's final distance) [m]",
                        float(np.linalg.norm(run_re.path[-1] - goal)) if run_off.converged and run_re.converged
                        else np.inf, 0.01, detail=f"{run_off.message}; {run_re.message}")
        sol.check_bound(f"{label}: the closed-loop motions coincide (Hausdorff distance of the two paths) [m]",
                        dev, 0.01, reference="second algorithm",
                        detail=f"{dev * 1000:.2f} mm; {len(run_off.path)} and {len(run_re.path)} iterates")
        sol.check(f"{label}: the reactive motion certified collision-free for its size (exact segment–obstacle "
                  "distances of its steps)", run_re.certified and run_re.min_clearance > 0,
                  f"min clearance {run_re.min_clearance:.3f} m")
    sol.value("path_length_reactive", float(np.sum(np.linalg.norm(np.diff(results["point robot"]["reactive"].path,
                                                                           axis=0), axis=1))), unit="m")
    fig, ax = subplots(figsize=(10, 5))
    draw_shapes(ax, obstacles, facecolor="0.75", label="obstacles")
    run_re = results["point robot"]["reactive"]
    qk = run_re.path[len(run_re.path) // 6]
    angles, ranges = range_scan(qk, obstacles, n_rays, R)
    ax.add_patch(Circle(qk, R, fill=False, ls=":", color="0.5"))
    hits = np.isfinite(ranges)
    P = qk + ranges[hits, None] * np.column_stack([np.cos(angles[hits]), np.sin(angles[hits])])
    ax.plot(P[:, 0], P[:, 1], "r.", ms=2, label=f"laser returns at one instant (R = {R:g} m)")
    for (label, r), (solid, dashed) in zip(results.items(), (("b-", "y--"), ("m-", "c--"))):
        ax.plot(r["offline"].path[:, 0], r["offline"].path[:, 1], solid, lw=2, label=f"{label}: off-line potential")
        ax.plot(r["reactive"].path[:, 0], r["reactive"].path[:, 1], dashed, lw=1.5, label=f"{label}: reactive (scan)")
    disc = results["disc robot"]["reactive"].path
    for q in disc[:: max(len(disc) // 12, 1)]:
        ax.add_patch(Circle(q, radius, fill=False, color="m", lw=0.6))
    return _potential_figure(sol, fig, ax, goal, (-0.5, 12.5, -3.5, 4),
                             "Fig. S12.6 — reactive planning with a laser range finder", "lower left")


@problem("12.13", "Wavefront navigation function on a grid: 1- vs 2-adjacency", kind="programming")
def problem_12_13() -> Solution:
    """Write a navigation-function planner on a grid (wavefront from the goal, cost = distance between
    cell centres) with 1- or 2-adjacency; compare the paths (Fig. S12.7).

    Grid, start (1, 1) and goal (7, 7) from the companion file s12_13. The navigation function is
    checked against scipy's Dijkstra on the grid graph; the path descends it strictly from the start to
    the goal. Manual: the 2-adjacency path is shorter, the 1-adjacency one at most √2 times longer in the
    same homotopy class; 2-adjacency paths may graze C-obstacles.
    """
    from scipy.sparse import lil_matrix
    from scipy.sparse.csgraph import dijkstra

    sol = Solution()
    occ = sol.given("occupancy grid", grid_12_13())
    start = sol.given("start cell (0-based)", (0, 0))
    goal = sol.given("goal cell (0-based)", (6, 6))     # cells (1, 1) and (7, 7), 1-based in the manual
    results = {}
    for adj in (1, 2):
        V = wavefront(occ, goal, adj)
        path = steepest_descent_path(V, start, adj)
        L = grid_path_length(path)
        n_r, n_c = occ.shape
        G = lil_matrix((occ.size, occ.size))
        steps = [(0, 1), (1, 0)] + ([(1, 1), (1, -1)] if adj == 2 else [])
        for i in range(n_r):
            for j in range(n_c):
                for di, dj in steps:
                    a, b = i + di, j + dj
                    if 0 <= a < n_r and 0 <= b < n_c and not occ[i, j] and not occ[a, b]:
                        G[i * n_c + j, a * n_c + b] = np.hypot(di, dj)
        ref = dijkstra(G.tocsr(), directed=False, indices=goal[0] * n_c + goal[1]).reshape(occ.shape)
        ref[occ] = np.inf
        results[adj] = (V, path, L)
        sol.value(f"navigation_function_{adj}adj", V, unit="cell (cell sides)")
        sol.value(f"path_{adj}adj", path + 1, unit="1 (cell indices, 1-based)")
        sol.value(f"length_{adj}adj", L, unit="cell (cell sides)")
        sol.check(f"{adj}-adjacency: wavefront = scipy's Dijkstra cost-to-go on every cell (∞ on obstacles)",
                  np.array_equal(np.isinf(V), np.isinf(ref)) and np.allclose(V[np.isfinite(V)], ref[np.isfinite(ref)]),
                  reference="other library")
        steps_ok = np.all(np.abs(np.diff(path, axis=0)).max(axis=1) == 1) and (
            adj == 2 or np.all(np.abs(np.diff(path, axis=0)).sum(axis=1) == 1))
        sol.check(f"{adj}-adjacency: path from (1,1) to (7,7) through free {4 * adj}-neighbours, V strictly decreasing",
                  tuple(path[0]) == start and tuple(path[-1]) == goal and steps_ok
                  and not occ[tuple(path.T)].any() and np.all(np.diff(V[tuple(path.T)]) < 0))
        sol.check_close(f"{adj}-adjacency: the descent path is a shortest path: its length = scipy's Dijkstra distance "
                        "from the start to the goal", L, ref[start], atol=1e-12, reference="other library")
    L1, L2 = results[1][2], results[2][2]
    sol.check("2-adjacency path shorter; L₂ ≤ L₁ ≤ √2 L₂", L2 < L1 <= np.sqrt(2) * L2 + 1e-12,
              f"L₁ = {L1:.4f}, L₂ = {L2:.4f}, ratio {L1 / L2:.4f}")
    p2 = results[2][1]
    diag = np.abs(np.diff(p2, axis=0)).sum(axis=1) == 2
    graze = [bool(occ[a[0], b[1]] or occ[b[0], a[1]]) for a, b, d in zip(p2[:-1], p2[1:], diag) if d]
    sol.value("diagonal_moves_grazing_obstacles", int(sum(graze)), unit="1")
    sol.check("2-adjacency path grazes a C-obstacle (a diagonal step past an obstacle corner)", any(graze))
    fig, axes = subplots(1, 2, figsize=(11, 6.0))
    for ax, adj in zip(axes, (1, 2)):
        V, path, L = results[adj]
        ax.imshow(occ, cmap="Greys", origin="upper", extent=[0.5, 7.5, 7.5, 0.5])
        for (i, j), v in np.ndenumerate(V):
            if np.isfinite(v):
                ax.text(j + 1, i + 1, f"{v:.1f}", ha="center", va="center", fontsize=7)
        ax.plot(path[:, 1] + 1, path[:, 0] + 1, "r-o", ms=4, label="path")
        ax.plot(start[1] + 1, start[0] + 1, "gs", ms=10, alpha=0.5, label="start (1, 1)")
        ax.plot(goal[1] + 1, goal[0] + 1, "b^", ms=10, alpha=0.5, label="goal (7, 7)")
        ax.fill([], [], color="k", label="obstacle cell")             # the occupancy map's colour key
        ax.set_xlabel("column j [cells]")
        ax.set_ylabel("row i [cells]")
        ax.set_title(f"{adj}-adjacency: path length {L:.3f}")
    # one legend under both maps: on a map it would hide cell values
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=4, fontsize=8)
    from matplotlib.layout_engine import TightLayoutEngine
    fig.suptitle("Fig. S12.7 — navigation function and path (values = cost-to-go, unit cells)")
    TightLayoutEngine(rect=(0, 0.06, 1, 1)).execute(fig)
    sol.figure(fig, tight=False)
    return sol
