"""ftfof: the Foot Trajectory and Force Optimization Framework for dry-adhesion climbing robots.

The package is the library (trajectory maths, constraint policy, kinematics, simulator, dataset,
surrogate, optimiser, evaluation, report) and, in ``ftfof.pipeline``, the application layer that
the stages share (jobs, files, digests, MLflow); the commands that read params live in the
sibling package ``stages``.
"""

__version__ = "0.1.0"
