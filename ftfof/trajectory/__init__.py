"""Foot trajectories: the three-segment C2 quintic Bezier, the baselines, the constraint policy
and the sampler of the climbable set."""
