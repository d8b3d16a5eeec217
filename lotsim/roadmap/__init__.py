"""The drivable graph of a built lot, a room for each of its parts: the graph as data
(:mod:`~lotsim.roadmap.model`), what can be driven to (:mod:`~lotsim.roadmap.reach`), the
assembler (:mod:`~lotsim.roadmap.assemble`: lanes cut into nodes, slots attached), junction
turns (:mod:`~lotsim.roadmap.junctions`, :mod:`~lotsim.roadmap.area_turns`,
:mod:`~lotsim.roadmap.through`), turnarounds at dead ends
(:mod:`~lotsim.roadmap.turnarounds`), multi-point turns at junctions
(:mod:`~lotsim.roadmap.junction_multipoints`), U-turns (:mod:`~lotsim.roadmap.uturns`), the
multi-point search they share (:mod:`~lotsim.roadmap.multipoint`), and the memo a caller
passes to reuse what one build of a lot's graph worked out in the next
(:mod:`~lotsim.roadmap.memo`); what tunes all of them is
:class:`~lotsim.roadmap.settings.RoadmapSettings` (:mod:`~lotsim.roadmap.settings`)."""
