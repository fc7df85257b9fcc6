"""One formatter for what a reader sees: 4 significant digits, rounding noise as 0, matrices as tables,
units; full precision only in the JSON."""

import json

import numpy as np
import pytest

from problems.format import format_number, format_value, format_value_html
from problems.registry import Solution
from problems.report import solution_dict, solution_html


@pytest.mark.parametrize("x, text", [
    (np.pi, "3.142"), (6.123233995736766e-17, "0"), (-2.0 / 3.0, "-0.6667"), (1234567.0, "1.235e+06"),
    (2.5e-7, "2.5e-07"), (np.int64(146), "146"), (True, "True"), (float("nan"), "nan"), (1 - 2j, "1 - 2j"),
])
def test_numbers_have_four_significant_digits_and_noise_is_zero(x, text):
    assert format_number(x) == text


def test_array_noise_is_zero_relative_to_the_largest_entry_but_small_arrays_keep_their_digits():
    assert format_value(np.array([0.8776, 2.9356e-17, -0.4794])) == "[0.8776, 0, -0.4794]"
    assert format_value(np.array([3e-13, 1e-13])) == "[3e-13, 1e-13]"   # an error measure, not noise


def test_matrix_is_a_multi_line_table_in_text_and_a_table_in_html():
    R = np.array([[np.cos(0.5), -np.sin(0.5), 0.0], [np.sin(0.5), np.cos(0.5), 0.0], [0.0, 0.0, 1.0]])
    text = format_value(R, "")
    lines = text.splitlines()
    assert len(lines) == 3 and lines[0].startswith("[[") and lines[2].endswith("]]")
    assert "0.8776" in lines[0] and "-0.4794" in lines[0] and len({len(l.rstrip("]")) for l in lines}) == 1
    html = format_value_html(R, "")
    assert html.count("<tr>") == 3 and html.count("<td>") == 9 and "<td>0.4794</td>" in html


def test_dict_is_one_key_per_line_and_a_nested_table():
    points = {"C": [0.45, -0.2], "D": [0.45, 0.0]}
    assert format_value(points, "m") == "C: [0.45, -0.2]\nD: [0.45, 0] m"
    assert format_value_html(points).count("<th>") == 2


def test_units_travel_from_solution_value_to_json_and_html_and_json_keeps_full_precision():
    sol = Solution(id="0.1", title="t", kind="numeric")
    sol.value("tau", np.array([98.10000000001, 6.1e-17]), unit="N·m")
    sol.check("ok", True)
    d = json.loads(json.dumps(solution_dict(sol)))
    assert d["units"] == {"tau": "N·m"} and d["values"]["tau"] == [98.10000000001, 6.1e-17]
    html = solution_html(d)
    assert "[98.1, 0]" in html and "N·m" in html and "98.10000000001" not in html
