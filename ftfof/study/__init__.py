"""Studies: one setting of a trajectory swept over a range on the platform (eps), and the
pipeline's presets and seeds swept as named experiments (sweep)."""
