"""A scenario from start to result: preparing its lot once (:mod:`~lotsim.sim.preparation`),
slot choice (:mod:`~lotsim.sim.assignment`), the event loop that plans each car as it
arrives and leaves (:mod:`~lotsim.sim.loop`), a run and the traffic it refuses
(:mod:`~lotsim.sim.running`), what a run gives back (:mod:`~lotsim.sim.results`), planning
orders (:mod:`~lotsim.sim.orders`), the settings of all of these
(:mod:`~lotsim.sim.settings`), validation reports (:mod:`~lotsim.sim.validation`) and run
budgets (:mod:`~lotsim.sim.limits`)."""
