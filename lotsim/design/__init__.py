"""Laying a lot out on a plot (``lotsim layout``, ``docs/layout.md``): from a plot's
outline, islands and gates to the scenario of the lot with the most bays that every
vehicle type can reach, park in and leave, ranked then by how well it serves traffic.

The package is named for lot design, not ``layout``, so that ``lotsim.layout`` is the
function (:func:`lotsim.api.layouts.layout`) and not a package.
:mod:`~lotsim.design.plot` holds the plot's specs and :mod:`~lotsim.design.plot_yaml` reads
them from a file; :mod:`~lotsim.design.candidates` draws candidate layouts (what they are
drawn as, :mod:`~lotsim.design.drawn`; their ring, :mod:`~lotsim.design.ring`; their gates'
aisles and mouths, :mod:`~lotsim.design.gates`; their bays packed into rows,
:mod:`~lotsim.design.packing`); :mod:`~lotsim.design.search` prepares, prunes, runs and
ranks them (how it searches, :mod:`~lotsim.design.settings`; a candidate prepared and run,
:mod:`~lotsim.design.preparing`; what it finds and how that ranks,
:mod:`~lotsim.design.results`).
"""
