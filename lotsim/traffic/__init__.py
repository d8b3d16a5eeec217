"""Many cars over time: demand (:mod:`~lotsim.traffic.demand`), the reservation table of
swept footprints (:mod:`~lotsim.traffic.reservation`) and the cooperative space-time search
against it (:mod:`~lotsim.traffic.search`)."""
