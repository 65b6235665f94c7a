"""The climbing robot's controller: the contact-force distribution and the slip reflexes."""
