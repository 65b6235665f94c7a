"""Search the trajectory space on the surrogates and choose one trajectory (FTFOF §V)."""
