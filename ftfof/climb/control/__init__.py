"""Planning and control of the climbing robot's body from its feet's friction and adhesion."""
