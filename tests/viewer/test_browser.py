"""An exported animation, served on 127.0.0.1 and rendered by headless Chromium (WebGL in SwiftShader).

The robot must be drawn (pixels of its colour where the arm is) and move between two animation times;
the page must load nothing from the network and log no console error. Screenshots are kept in
``$RMPC_ARTIFACTS`` (default ``<tmp>/rmpc-viewer-artifacts``), printed at the end of the test.

With ``CI=true`` a missing browser is a failure; elsewhere the test skips and says why.
"""

from __future__ import annotations

import functools
import http.server
import os
import tempfile
import threading
from pathlib import Path

import numpy as np
import pytest

from planners.timing import quintic
from rigid_body.robots import load
from viewer import export_html

CHROMIUM = Path("/usr/bin/chromium")
FLAGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--no-first-run", "--disable-background-networking", "--disable-component-update", "--disable-sync"]
SIZE = (640, 480)


def _browser_or_skip():
    reasons = []
    if not CHROMIUM.is_file():
        reasons.append(f"{CHROMIUM} is missing (apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sync_playwright = None
        reasons.append("playwright is not installed (pip install playwright)")
    if reasons:
        if os.environ.get("CI") == "true":
            pytest.fail("CI must run the browser test: " + "; ".join(reasons))
        pytest.skip("no headless browser: " + "; ".join(reasons))
    return sync_playwright


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    """A directory served over HTTP on 127.0.0.1 (an ephemeral port)."""
    root = tmp_path_factory.mktemp("served")
    handler = functools.partial(_QuietHandler, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield root, f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def page():
    """One headless Chromium page (fresh profile) recording console errors and every request."""
    sync_playwright = _browser_or_skip()
    profile = tempfile.mkdtemp(prefix="rmpc-chromium-")
    with sync_playwright() as p:
        context = p.chromium.launch_persistent_context(profile, executable_path=str(CHROMIUM), headless=True,
                                                       args=FLAGS, viewport={"width": SIZE[0], "height": SIZE[1]})
        pg = context.new_page()
        pg.errors, pg.requests = [], []
        pg.on("console", lambda m: pg.errors.append(m.text) if m.type == "error" else None)
        pg.on("pageerror", lambda e: pg.errors.append(str(e)))
        pg.on("request", lambda r: pg.requests.append(r.url))
        yield pg
        context.close()


def _artifacts() -> Path:
    path = Path(os.environ.get("RMPC_ARTIFACTS", Path(tempfile.gettempdir()) / "rmpc-viewer-artifacts"))
    path.mkdir(parents=True, exist_ok=True)
    return path


def _frame_at(page, time: float, name: str) -> np.ndarray:
    """Pause the animation at ``time`` seconds, let it render, screenshot it (kept as an artefact)."""
    page.evaluate("""t => new Promise(done => {
        viewer.animator.pause(); viewer.animator.seek(t); viewer.set_dirty();
        requestAnimationFrame(() => requestAnimationFrame(() => requestAnimationFrame(done)));
    })""", time)
    path = _artifacts() / f"{name}.png"
    page.screenshot(path=str(path))
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB")).astype(int)


def _robot_mask(image: np.ndarray) -> np.ndarray:
    """Pixels of the robot's orange, shaded: red dominant, some green, little blue (the background is
    blue, the grid grey, the x axes of the triads pure red)."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return (r > 150) & (g > 50) & (r > g + 40) & (g > b + 20)


def _open(page, served, robot, motion, name, **options):
    root, url = served
    export_html(robot, motion, root / f"{name}.html", **options)
    page.errors.clear()
    page.requests.clear()
    page.goto(f"{url}/{name}.html")
    page.wait_for_function("window.rmpcSceneReady === true", timeout=30_000)
    return url


def _assert_offline_and_clean(page, url):
    foreign = [r for r in page.requests if not r.startswith((url, "data:", "blob:"))]
    assert not foreign, f"the page fetched from elsewhere: {foreign[:5]}"
    assert not page.errors, f"console errors: {page.errors[:5]}"


def test_planar_arm_is_drawn_where_the_kinematics_puts_it_and_moves(page, served, capsys):
    """q from [0, 0] to [π/2, 0]. The arm's plane x–y is shown vertical (gravity −y points down) and seen
    square on: the arm starts along +x (right of the base, at the centre) and ends along +y (above it)."""
    robot = load("planar_2r")
    url = _open(page, served, robot, quintic([0.0, 0.0], [np.pi / 2, 0.0], 1.0, dt=0.01), "planar_2r",
                color="#e67319")
    start, end = _frame_at(page, 0.0, "planar_2r_t0"), _frame_at(page, 1.0, "planar_2r_t1")
    h, w = SIZE[1], SIZE[0]
    right = (slice(h // 2 - 20, h // 2 + 20), slice(w // 2 + 10, w))   # band along +x
    above = (slice(0, h // 2 - 10), slice(w // 2 - 20, w // 2 + 20))   # band along +y
    counts = {k: (int(_robot_mask(img)[right].sum()), int(_robot_mask(img)[above].sum()))
              for k, img in (("t0", start), ("t1", end))}
    with capsys.disabled():
        print(f"\n[viewer] planar_2r orange pixels (right band, upper band): {counts}; screenshots in {_artifacts()}")
    # the arm is a thick cylinder; what remains in the other band is the 1-px x axis of a triad
    assert counts["t0"][0] > 400 and counts["t0"][1] < 0.05 * counts["t0"][0], counts
    assert counts["t1"][1] > 400 and counts["t1"][0] < 0.05 * counts["t1"][1], counts
    _assert_offline_and_clean(page, url)


def test_panda_meshes_are_drawn_and_move(page, served, capsys):
    robot = load("panda")
    q0 = robot.configurations["neutral"].copy()
    q1 = q0 + np.array([1.2, 0.6, 0.0, -0.8, 0.0, 0.8, 0.0])
    url = _open(page, served, robot, quintic(q0, q1, 2.0, dt=0.02), "panda", color="#e67319")
    start, end = _frame_at(page, 0.0, "panda_t0"), _frame_at(page, 2.0, "panda_t1")
    m0, m1 = _robot_mask(start), _robot_mask(end)
    moved = int((m0 ^ m1).sum())
    with capsys.disabled():
        print(f"\n[viewer] panda pixels t0 {int(m0.sum())}, t1 {int(m1.sum())}, changed {moved}; "
              f"screenshots in {_artifacts()}")
    assert m0.sum() > 1500 and m1.sum() > 1500
    assert moved > 0.3 * m0.sum()
    _assert_offline_and_clean(page, url)


def test_ur5_meshes_are_lit_not_black(page, served, capsys):
    """The UR5's collision STL files carry zero normals: sent as triangles, the browser computes them
    (the file itself rendered the arm black)."""
    robot = load("ur5")
    q0 = np.array([0.0, -1.571, 1.571, -1.571, -1.571, 0.0])
    url = _open(page, served, robot, quintic(q0, q0 + 0.5, 1.0, dt=0.02), "ur5")
    image = _frame_at(page, 0.5, "ur5_t0.5")[25:]  # below meshcat's black "Open Controls" bar
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    grey = int(((r > 110) & (np.abs(r - g) < 20) & (np.abs(g - b) < 25)).sum())  # lit grey metal
    black = int(((r < 35) & (g < 35) & (b < 35)).sum())
    with capsys.disabled():
        print(f"\n[viewer] ur5 lit grey pixels {grey}, black pixels {black}")
    assert grey > 2000 and black < 0.05 * grey
    _assert_offline_and_clean(page, url)


def test_the_unicycle_of_11_16_is_drawn_and_drives_to_the_goal(page, served, capsys):
    """The report's export of Problem 11.16 (a generated mobile body, seen from above with x right and y
    up): the orange chassis starts at (−1, −2) and ends at the origin, up and to the right of it."""
    from problems.registry import solve
    from viewer import report_animations

    root, url = served
    report_animations(solve("11.16"), root)
    page.errors.clear()
    page.requests.clear()
    page.goto(f"{url}/animations/11.16_1.html")
    page.wait_for_function("window.rmpcSceneReady === true", timeout=30_000)
    masks = [_robot_mask(_frame_at(page, t, f"unicycle_11.16_t{t:g}")) for t in (0.0, 10.0)]
    counts = [int(m.sum()) for m in masks]
    (r0, c0), (r1, c1) = (np.argwhere(m).mean(axis=0) for m in masks)
    with capsys.disabled():
        print(f"\n[viewer] 11.16 unicycle orange pixels t0 {counts[0]}, t10 {counts[1]}; centroid moved "
              f"{c1 - c0:+.0f} px right, {r0 - r1:+.0f} px up")
    assert min(counts) > 200
    # (−1, −2) → (0, 0): right by half as much as up
    assert r0 - r1 > 60 and 0.25 < (c1 - c0) / (r0 - r1) < 0.8, (r0, c0, r1, c1)
    _assert_offline_and_clean(page, url)


def _animated_problem(k: int):
    """A registered-like problem whose solution animates the two-link arm (a different motion per k)."""
    from problems.registry import Problem, Solution

    def solve() -> Solution:
        """A test problem with a 3-D animation."""
        sol = Solution()
        sol.value("k", k, unit="1")
        sol.check("runs", True)
        sol.animation(load("planar_2r"), quintic([0.0, 0.0], [0.1 * k, -0.05 * k], 1.0, dt=0.02), f"motion {k}")
        return sol

    return Problem(f"0.{k}", f"animated test problem {k}", "simulation", solve)


def test_the_report_plays_every_animation_however_far_it_is_scrolled(page, served, capsys):
    """A written report with 20 animations (Chromium keeps 16 WebGL contexts): scrolled from top to bottom and back,
    at most a few animations are live at once, the one in view plays (its scene is drawn), and the console shows no
    WebGL context warning, no lost context, no error; every request stays on the page's server."""
    from problems.report import write_report
    from viewer.animation import MAX_LIVE_ANIMATIONS

    root, url = served
    write_report([_animated_problem(k) for k in range(1, 21)], root / "report")
    messages: list[str] = []
    page.on("console", lambda m: messages.append(f"{m.type}: {m.text}"))
    page.errors.clear()
    page.requests.clear()
    page.goto(f"{url}/report/index.html")
    page.wait_for_load_state("load")
    height = page.evaluate("document.documentElement.scrollHeight")
    most_live, seen_ready = 0, set()

    def ready_frames() -> set[str]:
        out = set()
        for frame in page.frames:
            if "/animations/" in frame.url:
                try:
                    if frame.evaluate("window.rmpcSceneReady === true"):
                        out.add(frame.url.rsplit("/", 1)[-1])
                except Exception:       # a frame removed while asked: released, fine
                    pass
        return out

    positions = list(range(0, height, 250)) + list(range(height, -1, -500)) + [0]
    for y in positions:
        page.evaluate("y => window.scrollTo(0, y)", y)
        page.wait_for_timeout(120)
        most_live = max(most_live, page.evaluate("window.rmpcLiveAnimations()"))
        seen_ready |= ready_frames()
    page.wait_for_function("document.querySelector('figure.animation iframe') !== null", timeout=10_000)
    first = page.frame_locator("figure.animation >> nth=0 >> iframe")
    first.locator("#meshcat-pane").wait_for(timeout=30_000)
    page.wait_for_timeout(2000)
    seen_ready |= ready_frames()
    # Chromium's own words: "WARNING: Too many active WebGL contexts. Oldest context will be lost.", "CONTEXT_LOST_WEBGL",
    # three.js's "THREE.WebGLRenderer: Context Lost." (SwiftShader's "GPU stall due to ReadPixels" is a performance note)
    bad = [m for m in messages if any(w in m.lower() for w in ("too many active webgl", "context lost", "context_lost",
                                                               "contextlost", "will be lost")) or m.startswith("error")]
    with capsys.disabled():
        print(f"\n[viewer] report of 20 animations, {height} px scrolled down and back: at most {most_live} live at "
              f"once, {len(seen_ready)} played; console: {len(messages)} messages, {len(bad)} WebGL/lost/error: "
              f"{[m[:90] for m in messages]}")
    assert 0 < most_live <= MAX_LIVE_ANIMATIONS
    assert len(seen_ready) == 20, sorted(seen_ready)           # every animation played when it came into view
    assert "0.1_1.html" in ready_frames()                       # and the first one plays again at the top
    assert not bad, bad[:5]
    _assert_offline_and_clean(page, url)
