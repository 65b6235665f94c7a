"""Studies: one setting of a trajectory swept over a range on the platform (eps), the
pipeline's presets and seeds swept as named experiments (sweep), and how long a whole run of
params takes (duration)."""
