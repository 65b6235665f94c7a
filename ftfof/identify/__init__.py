"""Friction and adhesion of a surface from a slip test's contact forces (climbing_slip §4)."""
