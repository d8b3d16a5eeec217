"""The drivable graph of a built lot: lanes cut into nodes, the turns that join them at
junctions and across areas, U-turns and multi-point turns, and each slot's park and leave
edges (:func:`~lotsim.roadmap.graph.build_graph`, :class:`~lotsim.roadmap.graph.LotGraph`)."""
