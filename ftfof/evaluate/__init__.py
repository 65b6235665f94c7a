"""Simulator-verified evaluation: Table I analogue, surrogate fidelity, controller export."""
