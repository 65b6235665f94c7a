"""ftfof: the Foot Trajectory and Force Optimization Framework for dry-adhesion climbing robots.

The package is the pure library (trajectory maths, constraint policy, kinematics, simulator,
dataset, surrogate, optimiser, report); the pipeline stages that read params and write files live
in the sibling package ``stages``.
"""

__version__ = "0.1.0"
