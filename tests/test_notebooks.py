"""Every notebook executes top to bottom without an error, and no cell shows a failed check."""

import re
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOKS = sorted((Path(__file__).resolve().parent.parent / "notebooks").glob("*.ipynb"))

# A failed check as the notebooks print it: "FAIL name — detail", "[FAIL] name" (rmpc solve), or the
# ✘ of a Solution's HTML view.
FAILED = re.compile(r"(^|\n)\s*(\[FAIL\]|FAIL\b)|✘")


def failed_outputs(nb) -> list[str]:
    """The outputs (text or HTML) of the code cells that show a failed check."""
    found = []
    for k, cell in enumerate(nb.cells):
        for out in cell.get("outputs", []) if cell.cell_type == "code" else []:
            texts = [out.get("text", "")] + [str(v) for key, v in out.get("data", {}).items()
                                             if key in ("text/plain", "text/html", "text/markdown")]
            for text in texts:
                match = FAILED.search(text)
                if match:
                    found.append(f"cell {k}: …{text[max(0, match.start() - 40):match.end() + 80]}…")
    return found


def test_the_scan_sees_a_failed_check():
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("")])
    nb.cells[0].outputs = [nbformat.v4.new_output("stream", text="PASS a — ok\nFAIL b — 2e-3\n")]
    assert failed_outputs(nb)
    nb.cells[0].outputs = [nbformat.v4.new_output("display_data", data={"text/html": "<li>✘ <b>x</b></li>"})]
    assert failed_outputs(nb)
    nb.cells[0].outputs = [nbformat.v4.new_output("stream", text="PASS a — FAILSAFE\n")]
    assert not failed_outputs(nb)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_executes(path, tmp_path, monkeypatch):
    # the kernel runs in tmp_path; examples/ (not installed) is found in the source tree, as from notebooks/ ("..")
    monkeypatch.setenv("PYTHONPATH", str(path.parent.parent))
    nb = nbformat.read(path, as_version=4)
    # startup_timeout: a kernel on a loaded 2-core machine may take over nbclient's default 60 s to answer
    NotebookClient(nb, timeout=300, startup_timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    failed = failed_outputs(nb)
    assert not failed, f"{path.name} shows failed checks: {failed}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.name for p in NOTEBOOKS])
def test_notebook_is_committed_with_its_outputs_and_figures_as_images(path):
    """GitHub shows a committed notebook read-only: its cells carry their outputs, and a returned figure is an
    image (``%matplotlib inline``), not the text ``<Figure size 640x480 with 1 Axes>``."""
    nb = nbformat.read(path, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code" and c.source.strip()]
    with_outputs = [c for c in code if c.get("outputs")]
    assert len(with_outputs) >= len(code) // 2, f"{path.name}: {len(with_outputs)} of {len(code)} cells have outputs"
    for k, cell in enumerate(code):
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            text = str(data.get("text/plain", ""))
            assert not (text.startswith("<Figure size") and "image/png" not in data), \
                f"{path.name}, code cell {k}: a figure stored as text"
