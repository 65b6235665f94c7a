"""The single-leg platform in Exudyn: film, pad and bond law, the acquisition protocol, the
parallel pool, and the calibration of a surface to Table I."""
