"""The climbing robot: the whole quadruped on a vertical wall in Exudyn (docs/climb.md).

Library layer: the sagittal leg chains, the crawl gait, the Exudyn model with four pads of
:mod:`ftfof.sim`'s film and bond law, its solver loop, the IMU and the per-step metrics; in
:mod:`ftfof.climb.control`, the one-step CoM planner that keeps every pad in its friction cone.
"""
