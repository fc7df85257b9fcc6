"""Per-problem solutions of the book's end-of-chapter problems, the registry and the ``rmpc`` CLI."""

from problems.registry import Check, Solution, all_problems, get, problem, solve

__all__ = ["Check", "Solution", "all_problems", "get", "problem", "solve"]
