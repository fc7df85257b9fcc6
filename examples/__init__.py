"""Demos beyond the book on real robots (example-robot-data), importable by notebooks and tests.

Layering: ``examples`` sits above ``problems`` (it may use the problems' ``Solution`` and figure
helpers); nothing below imports it, and no registered problem depends on it.
"""
