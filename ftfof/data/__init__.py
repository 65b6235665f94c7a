"""Simulated and imported steps as data: the acquisition schema, the dataset of fixed-length
sequences, the surrogate targets, and the rules a step is judged by (release, landing, shake)."""
