"""The climbing robot under slip: the body planned from its feet's friction and adhesion, the
contact-force distribution and the slip reflexes (climbing-under-slip method)."""
