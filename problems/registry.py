"""The problem registry: every end-of-chapter problem is a function registered with its id.

A problem function takes no argument, builds the problem's data, calls the library and returns a
:class:`Solution` holding named values, checks (comparisons with the manual, properties that the
figures show) and matplotlib figures. ``@problem("2.15", "title", kind="numeric")`` registers it.
"""

from __future__ import annotations

import difflib
import importlib
import inspect
import pkgutil
import re
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

KINDS = ("derivation", "numeric", "simulation", "programming", "qualitative")

#: What a check compares with: the kind of its independent reference. ``"property"`` is a bare
#: boolean statement (a named property the figures show); every comparison names its reference.
#: ``"specification met"``: the expected side is a requirement of the data (ζ, X_R, a bandwidth) and the
#: actual side the designed system evaluated on a separate path (poles or gains by python-control).
#: ``"independent derivation"``: a value derived independently of rmpc, not printed in the manual (the spec
#: catalogue's [D] and "derived values" entries: numpy/scipy/Pinocchio computations made while writing it).
REFERENCES = ("manual number", "closed form", "finite differences", "second algorithm", "other library",
              "simulation vs prediction", "specification met", "independent derivation", "property")


#: How ``actual`` relates to ``expected``: equal within a tolerance, an error measure whose ideal is 0,
#: or a bound (``expected`` a limit or a requirement that ``actual`` must not cross).
RELATIONS = ("==", "error", "<=", "<", ">=", ">")


def _reference(reference: str | None) -> str | None:
    if reference is not None and reference not in REFERENCES:
        raise ValueError(f"reference must be one of {REFERENCES} or None, got {reference!r}")
    return reference


@dataclass(frozen=True)
class Check:
    """One verified statement: a comparison with an independent reference, or a named property.

    ``actual`` and ``expected`` are the two sides as given (kept as objects, so a test can tell a value
    compared with itself); ``reference`` the kind of reference (:data:`REFERENCES`, ``None`` when the
    check does not say); ``relation`` how ``actual`` relates to ``expected`` (:data:`RELATIONS`;
    a comparison recorded without one is read as an equality).
    """

    name: str
    passed: bool
    detail: str = ""
    actual: Any = None
    expected: Any = None
    reference: str | None = None
    relation: str = "=="


@dataclass
class Solution:
    """What a problem function returns: named values, checks and figures."""

    id: str = ""
    title: str = ""
    kind: str = ""
    values: dict[str, Any] = field(default_factory=dict)
    checks: list[Check] = field(default_factory=list)
    figures: list[Any] = field(default_factory=list)  # matplotlib Figure objects
    animations: list[dict[str, Any]] = field(default_factory=list)  # 3-D animations for the report (viewer/)
    units: dict[str, str] = field(default_factory=dict)  # value name -> unit ("m", "rad", "N·m", …)
    data: dict[str, Any] = field(default_factory=dict)  # the problem's given data (sol.given): no check expects these
    statement: str = ""  # the problem function's docstring, first paragraph: what is asked, the data

    @property
    def passed(self) -> bool:
        """True when there is at least one check and every check passed."""
        return bool(self.checks) and all(c.passed for c in self.checks)

    def value(self, name: str, value: Any, unit: str = "") -> Any:
        """Record a named value (with its ``unit``, e.g. ``"rad"``, ``"N·m"``) and return it (so it
        can be used inline)."""
        self.values[name] = value
        if unit:
            self.units[name] = unit
        return value

    def given(self, name: str, value: Any, unit: str = "") -> Any:
        """Declare a datum of the problem statement (with its ``unit``) and return it. A check whose
        ``expected`` is a given datum echoes the input back; the problems' lint rejects it."""
        self.data[name] = value
        if unit:
            self.units[name] = unit
        return value

    def check(self, name: str, passed: bool, detail: str = "", reference: str | None = "property", *,
              actual: Any = None, expected: Any = None, relation: str = "==") -> bool:
        """Record a check; ``passed`` is coerced to ``bool``. A bare boolean is a named ``"property"``;
        a comparison written by hand names its ``reference``, may record both sides and says whether
        it is an equality (``"=="``) or a bound (``"<="``: ``actual`` ≤ ``expected``, e.g. a torque
        limit or a settling-time requirement of the data; :data:`RELATIONS`)."""
        if relation not in RELATIONS:
            raise ValueError(f"relation must be one of {RELATIONS}, got {relation!r}")
        self.checks.append(Check(name, bool(passed), detail, actual, expected, _reference(reference), relation))
        return bool(passed)

    def check_bound(self, name: str, actual: float, bound: float, relation: str = "<=",
                    reference: str | None = "property", detail: str = "") -> bool:
        """Record that ``actual`` satisfies ``actual <relation> bound`` (a limit or a requirement,
        possibly a datum of the problem: a bound is not an echo, since ``actual`` can cross it); NaN fails."""
        if relation not in ("<=", "<", ">=", ">"):
            raise ValueError(f"relation must be one of '<=', '<', '>=', '>', got {relation!r}")
        a, b = float(actual), float(bound)
        ok = {"<=": a <= b, "<": a < b, ">=": a >= b, ">": a > b}[relation]
        return self.check(name, ok, detail or f"{a:.6g} {relation} {b:.6g}", reference,
                          actual=actual, expected=bound, relation=relation)

    def check_close(self, name: str, actual: Any, expected: Any, *, atol: float = 1e-9,
                    rtol: float = 0.0, reference: str | None = None) -> bool:
        """Record a numerical comparison ``|actual - expected| <= atol + rtol |expected|``; ``reference``
        says what ``expected`` is (:data:`REFERENCES`)."""
        a = np.asarray(actual, dtype=complex if np.iscomplexobj(actual) else float)
        e = np.asarray(expected, dtype=complex if np.iscomplexobj(expected) else float)
        if a.shape != e.shape:
            return self.check(name, False, f"shape {a.shape} != expected {e.shape}", reference,
                              actual=actual, expected=expected)
        err = np.abs(a - e)
        ok = bool(np.all(np.isfinite(a)) and np.all(err <= atol + rtol * np.abs(e)))
        max_err = float(np.max(err)) if err.size else 0.0
        return self.check(name, ok, f"max |error| = {max_err:.3g} (atol {atol:g}, rtol {rtol:g})", reference,
                          actual=actual, expected=expected)

    def animation(self, robot: Any, motion: Any, title: str = "", **options: Any) -> None:
        """Attach a 3-D animation of ``robot`` along ``motion`` (a SimulationResult, a Trajectory or
        ``(t, q)``); the report exports it with ``viewer.report_animations``. ``options`` go to
        ``viewer.animate`` (``speed``, ``overlays=lambda scene: ...``, ``tracks``)."""
        self.animations.append({"robot": robot, "motion": motion, "title": title, **options})

    def check_error(self, name: str, error: float, tol: float, reference: str | None = None,
                    detail: str = "") -> bool:
        """Record that an error measure (e.g. the largest difference from an independent reference over
        many samples) is below ``tol``; NaN fails. ``actual`` is the error, ``expected`` 0; ``detail``, if
        given, follows the error in the check's detail."""
        error = float(error)
        text = f"max |error| = {error:.2g} (< {tol:g})" + (f"; {detail}" if detail else "")
        return self.check(name, error < tol, text, reference, actual=error, expected=0.0, relation="error")

    def figure(self, fig: Any, title: str | None = None, tight: bool = True) -> Any:
        """The figure epilogue: give ``fig`` its title (``suptitle``, also its file name in a report),
        lay it out (``tight_layout``) and attach it; returns it."""
        if title is not None:
            fig.suptitle(title)
        if tight:  # the tight layout applied once, without leaving an engine on the figure: a figure with
            # one (even the placeholder ``fig.tight_layout()`` leaves) is drawn twice by each ``savefig``
            from matplotlib.layout_engine import TightLayoutEngine
            TightLayoutEngine().execute(fig)
        self.figures.append(fig)
        return fig

    def __repr__(self) -> str:
        """One line (a notebook shows :meth:`_repr_html_`; ``print(sol)`` the values and checks)."""
        ok = sum(c.passed for c in self.checks)
        return (f"Solution({self.id!r}, {self.title!r}, {len(self.values)} values, {ok}/{len(self.checks)} "
                f"checks passed, {len(self.figures)} figures)")

    def __str__(self) -> str:
        """What ``rmpc solve ID`` prints: title, values (4 significant digits, units), checks, verdict."""
        from problems.format import solution_text

        return solution_text(self)

    def _repr_html_(self) -> str:
        """Jupyter's view: title, values table, checks (✔/✘), figures inline as PNG."""
        from problems.report import inline_html

        return inline_html(self)


@dataclass(frozen=True)
class Problem:
    """A registered problem. One listed from :mod:`problems.index` (not imported yet) has no function
    until it is asked for: ``function`` then imports its chapter module (``problems.<module>``)."""

    id: str
    title: str
    kind: str
    _function: Callable[[], Solution] | None = field(default=None, repr=False)
    module: str = ""

    @property
    def function(self) -> Callable[[], Solution]:
        if self._function is not None:
            return self._function
        importlib.import_module(f"problems.{self.module}")
        return _REGISTRY[self.id].function

    @property
    def chapter(self) -> int:
        return int(self.id.split(".")[0])

    def solve(self) -> Solution:
        sol = self.function()
        if not isinstance(sol, Solution):
            raise TypeError(f"problem {self.id} returned {type(sol).__name__}, not a Solution")
        sol.id, sol.title, sol.kind = self.id, self.title, self.kind
        sol.statement = sol.statement or self.statement
        return sol

    @property
    def statement(self) -> str:
        """The first paragraph of the problem function's docstring (the problem and its data)."""
        doc = inspect.getdoc(self.function) or ""
        return " ".join(doc.split("\n\n")[0].split())


_REGISTRY: dict[str, Problem] = {}


def problem(id: str, title: str, kind: str = "derivation") -> Callable:
    """Decorator registering a problem function under the book's id, e.g. ``"3.21"``."""
    if not re.fullmatch(r"\d{1,2}\.\d{1,2}", id):
        raise ValueError(f"problem id must look like '3.21', got {id!r}")
    if kind not in KINDS:
        raise ValueError(f"problem {id}: kind must be one of {KINDS}, got {kind!r}")

    def register(function: Callable[[], Solution]) -> Callable[[], Solution]:
        if id in _REGISTRY and _REGISTRY[id].function.__qualname__ != function.__qualname__:
            raise ValueError(f"problem {id} is registered twice")
        _REGISTRY[id] = Problem(id, title, kind, function, function.__module__.rpartition(".")[2])
        return function

    return register


def _id_key(id: str) -> tuple[int, int]:
    chapter, number = id.split(".")
    return int(chapter), int(number)


def load_all() -> None:
    """Import every ``problems/chNN.py`` (or ``chNN_part.py``) module so that its problems register."""
    import problems

    for info in pkgutil.iter_modules(problems.__path__):
        if re.fullmatch(r"ch\d\d(_[a-z_]+)?", info.name):
            importlib.import_module(f"problems.{info.name}")


def _indexed() -> dict[str, Problem]:
    """The problems of :mod:`problems.index` (id, kind, title, module; no chapter module imported),
    the ones already registered in their place, with those registered elsewhere (tests) added."""
    from problems.index import PROBLEMS

    listed = {id: _REGISTRY.get(id) or Problem(id, title, kind, None, module) for id, kind, title, module in PROBLEMS}
    return {**listed, **_REGISTRY}


def all_problems() -> list[Problem]:
    """Every problem, in the book's order; a chapter module is imported when one of its problems is solved."""
    problems = _indexed()
    return [problems[k] for k in sorted(problems, key=_id_key)]


def get(id: str) -> Problem:
    """The problem with this id (its chapter module imported); ``KeyError`` naming the nearest ids otherwise."""
    problems = _indexed()
    if id not in problems:
        near = difflib.get_close_matches(id, list(problems), n=5, cutoff=0.5)
        hint = f"; nearest: {', '.join(near)}" if near else ""
        raise KeyError(f"unknown problem id {id!r}{hint} (see 'rmpc list')")
    problems[id].function  # imports its chapter, so that _REGISTRY holds it
    return _REGISTRY[id]


def solve(id: str) -> Solution:
    """Solve one problem by id."""
    return get(id).solve()


def index_source() -> str:
    """The text of ``problems/index.py`` for the problems of the chapter modules (:func:`write_index`)."""
    load_all()
    rows = [f"    ({p.id!r}, {p.kind!r}, {p.title!r}, {p.module!r}),"
            for p in sorted(_REGISTRY.values(), key=lambda p: _id_key(p.id)) if re.fullmatch(r"ch\d\d(_[a-z_]+)?", p.module)]
    return ('"""Generated by ``problems.registry.write_index()``: (id, kind, title, chapter module) of every problem, so\n'
            "that ``rmpc list`` and ``rmpc solve ID`` need not import every chapter. Regenerate it after adding or\n"
            'renaming a problem (tests/problems/test_index.py checks that it is current)."""\n\n'
            "PROBLEMS = (\n" + "\n".join(rows) + "\n)\n")


def write_index() -> None:
    """Regenerate ``problems/index.py`` from the chapter modules."""
    from pathlib import Path

    (Path(__file__).parent / "index.py").write_text(index_source(), encoding="utf-8")
