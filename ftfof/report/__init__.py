"""Figures and the self-contained HTML report, drawn from values the other packages computed."""
