"""The legs' kinematics and the limits they put on the foot: reachable positions (Ppl) and
velocities (Vpl)."""
