"""A surface's parameters from measurements: friction and adhesion from a slip test's contact
forces (climbing_slip §4), and what a fit to FTFOF Table I may fit or hold (calibration)."""
