"""One car into one slot: the parking maneuver planner with its per-lot answer cache
(:mod:`~lotsim.maneuvers.planner`) and the minimum-slot planner for parallel slots
(:mod:`~lotsim.maneuvers.minslot`)."""
