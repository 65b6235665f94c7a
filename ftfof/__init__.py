"""ftfof: the Foot Trajectory and Force Optimization Framework for dry-adhesion climbing robots.

The package is the library (trajectory maths, constraint policy, kinematics, simulator, dataset,
surrogate, optimiser, evaluation, report) and, in ``ftfof.pipeline``, the application layer that
the stages share (jobs, files, digests, MLflow); the commands that read params live in the
sibling package ``stages``.
"""

from ftfof.version import __version__

__all__ = ["__version__", "open_run"]


def __getattr__(name: str):
    """``ftfof.open_run``, imported on first use: the package itself stays light."""
    if name == "open_run":
        from ftfof.pipeline.notebook import open_run

        return open_run
    raise AttributeError(f"module 'ftfof' has no attribute {name!r}")
