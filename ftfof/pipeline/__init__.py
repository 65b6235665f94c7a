"""The application layer: what the pipeline's stages share beyond the pure library (resumable
jobs, atomic files, digests, MLflow tracking, registry and run links) and one module per stage run.

It may write files and talk to MLflow; it never reads params.yaml (the stages hand it ``Params``).
"""
