"""Studies: one setting of a trajectory swept over a range on the platform, and what it does."""
