"""The scenario's ``routes`` section: the service vehicles' routes a lot must carry.

Each route names its vehicle (a service vehicle or a car of the catalogue), where it
starts (an entrance, or a pose), where it must reach (a building entrance, a pose or an
exit) and the exits it may then leave by. Every name is checked against the lot as
written, and every problem is located (``file:line:col: routes[0].to: ...``).
"""

from __future__ import annotations

import math

from lotsim.io.yamlnodes import YNode
from lotsim.lot.spec import LotSpec
from lotsim.roadmap.service_routes import BAYS, RoutePlace, RouteSpec
from lotsim.vehicles.catalogue import CATALOGUE, SERVICE_VEHICLES, route_vehicle

MAX_ROUTES = 50
"""Most routes a scenario may hold: each is a search of its own."""
DEFAULT_WITHIN = 18.0
"""How near [m] the vehicle's body must come to a building entrance unless a route says:
the distance from a pump appliance to a fire main's inlet in "Approved Document B (Fire
safety), Volume 2" (HM Government, 2019), paragraph 15.1."""

_KEYS = ("id", "vehicle", "from", "to", "leave", "bays")


def parse_routes(node: YNode, lot: LotSpec) -> tuple[RouteSpec, ...]:
    """Validate the ``routes`` list against ``lot``'s entrances, exits and building
    entrances."""
    out = []
    seen: dict[str, int] = {}
    for item in node.items(min_len=1, max_len=MAX_ROUTES):
        route = _route(item, lot)
        if route.id in seen:
            raise item.error(f"route {route.id!r} is given twice (first on line "
                             f"{seen[route.id]})")
        seen[route.id] = item.where.line
        out.append(route)
    return tuple(out)


def _route(node: YNode, lot: LotSpec) -> RouteSpec:
    f = node.fields(required=["id", "vehicle", "from", "to"], optional=["leave", "bays"])
    rid = f["id"].ident()
    name = f["vehicle"].string(choices=[*SERVICE_VEHICLES, *CATALOGUE])
    entrances = [p.id for p in lot.entrances]
    exits = [p.id for p in lot.exits]
    start = _start(f["from"], entrances)
    goal = _goal(f["to"], lot, exits)
    leave: tuple[str, ...] = ()
    if "leave" in f:
        n = f["leave"]
        if not exits:
            raise n.error("the lot has no exits to leave by")
        nodes = n.items(min_len=1) if n.is_sequence else [n]
        leave = tuple(dict.fromkeys(x.string(choices=exits) for x in nodes))
        if goal.kind == "exit":
            raise n.error("a route that goes to an exit has left already: drop 'leave'")
    bays = f["bays"].string(choices=BAYS) if "bays" in f else "full"
    return RouteSpec(rid, route_vehicle(name), start, goal, leave, bays, where=node.where)


def _pose(node: YNode) -> tuple[float, float, float]:
    f = node.fields(required=["x", "y", "heading_deg"])
    return (f["x"].length(), f["y"].length(),
            math.radians(f["heading_deg"].number(min=-360, max=360)))


def _start(node: YNode, entrances: list[str]) -> RoutePlace:
    """An entrance's id, or a pose ``{x, y, heading_deg}``."""
    if node.is_mapping:
        return RoutePlace("pose", pose=_pose(node), where=node.where)
    if not entrances:
        raise node.error("the lot has no entrances: give a pose {x, y, heading_deg}")
    return RoutePlace("entrance", node.string(choices=entrances), where=node.where)


def _goal(node: YNode, lot: LotSpec, exits: list[str]) -> RoutePlace:
    """``{building_entrance: ID, within: M}``, ``{exit: ID}`` or ``{x, y, heading_deg}``."""
    if not node.is_mapping:
        raise node.error("expected a mapping: {building_entrance: ID, within: M}, "
                         "{exit: ID} or a pose {x, y, heading_deg}")
    keys = {k.value for k, _ in node.node.value if hasattr(k, "value")}
    if "building_entrance" in keys:
        f = node.fields(required=["building_entrance"], optional=["within"])
        doors = {b.id: b.point for b in lot.building_entrances}
        if not doors:
            raise f["building_entrance"].error("the lot has no building_entrances")
        door = f["building_entrance"].string(choices=list(doors))
        within = (f["within"].length(min=0, max=200) if "within" in f
                  else DEFAULT_WITHIN)
        x, y = doors[door]
        return RoutePlace("building_entrance", door, point=(float(x), float(y)),
                          within=within, where=node.where)
    if "exit" in keys:
        f = node.fields(required=["exit"])
        if not exits:
            raise f["exit"].error("the lot has no exits")
        return RoutePlace("exit", f["exit"].string(choices=exits), where=node.where)
    return RoutePlace("pose", pose=_pose(node), where=node.where)
