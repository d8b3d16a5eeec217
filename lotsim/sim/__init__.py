"""A scenario from start to result: preparing its lot once, the event loop that plans each
car as it arrives and leaves (:mod:`~lotsim.sim.simulation`), planning orders
(:mod:`~lotsim.sim.orders`), validation reports (:mod:`~lotsim.sim.validation`) and run
budgets (:mod:`~lotsim.sim.limits`)."""
