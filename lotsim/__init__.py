"""lotsim: plan many car-like vehicles in a parking lot.

The pipeline runs one way: a scenario YAML is loaded and validated into frozen
specs (:mod:`lotsim.io`), the lot layout is built into slot polygons and lanes
(:mod:`lotsim.lot`), and the lanes into a drivable :class:`networkx.DiGraph`
(:mod:`lotsim.lot.graph`) that vehicles (:mod:`lotsim.vehicles`) travel.
"""

__version__ = "0.1.0"
