"""Laying a lot out on a plot (``lotsim layout``, ``docs/layout.md``): from a plot's
outline, islands and gates to the scenario of the lot with the most bays that every
vehicle type can reach, park in and leave, ranked then by how well it serves traffic.

:mod:`~lotsim.layout.plot` holds the plot's specs and :mod:`~lotsim.layout.plot_yaml` reads
them from a file; :mod:`~lotsim.layout.candidates` draws candidate layouts;
:mod:`~lotsim.layout.search` prepares, prunes, runs and ranks them.
"""
