"""The book's end-of-chapter problems, the registry and the ``rmpc`` command line.

Entry points: ``solve("8.10")`` → a :class:`Solution` (``values``, ``checks``, ``figures``; shown as a
table in a notebook), ``all_problems()``, ``get(id)``; one module per chapter (``ch02`` … ``ch12``)
registers its problems with ``@problem``; ``cli`` is the ``rmpc`` command and ``report`` the HTML report.
"""

from problems.registry import Check, Solution, all_problems, get, problem, solve

__all__ = ["Check", "Solution", "all_problems", "get", "problem", "solve"]
