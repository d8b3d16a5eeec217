"""``lotsim cars``: the built-in vehicle types."""

from __future__ import annotations

import argparse
import math

from lotsim import api
from lotsim.cli.output import EXIT_OK

HELP = "list the built-in vehicle types"
EXITS = "0 listed"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """None: the list is all there is."""


def execute(args: argparse.Namespace) -> int:
    print(f"{'name':8} {'length':>7} {'width':>6} {'wheelbase':>9} {'max steer':>9} {'R':>6}")
    for v in api.CATALOGUE.values():
        print(
            f"{v.name:8} {v.length:6.3f}m {v.width:5.3f}m {v.wheelbase:8.3f}m "
            f"{math.degrees(v.max_steer):8.2f}° {v.min_turning_radius:5.2f}m"
        )
    print("R: minimum turning radius of the rear-axle centre, wheelbase / tan(max steer)")
    return EXIT_OK
