"""Search the trajectory space on the surrogates and choose one trajectory (DESIGN §9-§10)."""
