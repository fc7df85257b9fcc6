"""Chapter 9: registration and the required value keys."""

import numpy as np

from problems.registry import all_problems, get


def test_problems_9_1_to_9_11_are_registered():
    kinds = {p.id: p.kind for p in all_problems()}
    for i in range(1, 12):
        assert f"9.{i}" in kinds
    assert kinds["9.3"] == kinds["9.10"] == "simulation"


def test_required_value_keys_of_9_3():
    sol = get("9.3").solve()
    np.testing.assert_allclose(sol.values["f_final"], [0.0, -250.0], atol=0.5)
    np.testing.assert_allclose(sol.values["position_error_final"], [0.0, -0.05], atol=5e-4)
    # its 3-D animation: the arm, the plane, the force arrow; 0.4 m for the −500 N of t = 0 (the tip 0.1 m in)
    (anim,) = sol.animations
    t, q = anim["motion"]
    arrows = anim["tracks"]["force"]
    assert np.allclose(np.diff(t), 0.04) and arrows.shape == (t.size, 4, 4)
    np.testing.assert_allclose(np.linalg.norm(arrows[0][:3, 1]), 8e-4 * 500.0, rtol=1e-6)
    # the arrow (the plane's reaction) along the plane's outward normal y_c = [−1, 1]/√2
    direction = arrows[0][:3, 1] / np.linalg.norm(arrows[0][:3, 1])
    np.testing.assert_allclose(direction, [-np.sqrt(0.5), np.sqrt(0.5), 0.0], atol=1e-9)


def test_animations_export_small_html(tmp_path):
    """9.10's animation exports to one offline HTML file of about 1 MB (25 frames per second)."""
    from viewer import report_animations

    sol = get("9.10").solve()
    (snippet,) = report_animations(sol, tmp_path)
    files = list((tmp_path / "animations").glob("*.html"))
    assert len(files) == 1 and f'data-src="animations/{files[0].name}"' in snippet   # made live by the report page
    assert files[0].stat().st_size < 2e6
