"""The application layer: what the pipeline's stages share beyond the pure library (MLflow
registry and tracking conventions, resumable jobs)."""
