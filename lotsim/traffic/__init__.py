"""Many cars over time: demand (:mod:`~lotsim.traffic.demand`); swept volumes
(:mod:`~lotsim.traffic.swept`); the reservation table of swept footprints
(:mod:`~lotsim.traffic.reservation`, with its entry store, space-time grid and candidate
pairs in :mod:`~lotsim.traffic.store`, :mod:`~lotsim.traffic.grid` and
:mod:`~lotsim.traffic.candidates`); the lot graph as a vehicle type drives it
(:mod:`~lotsim.traffic.searchgraph`) with its RRA* heuristic
(:mod:`~lotsim.traffic.heuristic`); the cooperative space-time search against the table
(:mod:`~lotsim.traffic.search`), tuned by :mod:`~lotsim.traffic.settings`, answering with
plans (:mod:`~lotsim.traffic.plans`)."""
