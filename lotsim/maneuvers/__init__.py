"""One car into one slot, in OMPL's shape: the problem (:mod:`~lotsim.maneuvers.problem`),
its validity checks (:mod:`~lotsim.maneuvers.validity`), the searches — a shuffle out of a
perpendicular or angled bay (:mod:`~lotsim.maneuvers.shuffle`), the minimum-slot strokes into
a parallel slot (:mod:`~lotsim.maneuvers.strokes`, :mod:`~lotsim.maneuvers.minslot`), both
ended by a closing move onto the lane (:mod:`~lotsim.maneuvers.closing`) — easing
(:mod:`~lotsim.maneuvers.easing`), the planner with its per-lot answer cache
(:mod:`~lotsim.maneuvers.planner`), the batch over a lot (:mod:`~lotsim.maneuvers.batch`),
the maneuver itself (:mod:`~lotsim.maneuvers.maneuver`) and the settings
(:mod:`~lotsim.maneuvers.settings`)."""
