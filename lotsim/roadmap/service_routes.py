"""Service routes: can a fire appliance or a refuse truck drive through the lot?

A lot designer checks that the service vehicles of a site (a fire appliance to the
building's front, a refuse truck to the bin store) can reach where they must and leave,
with the bays full. :func:`plan_route` plans one such route on the lot's paved ground,
clear of its walls, islands, obstacles, access aisles and bays, with the multi-point
Hybrid A* the roadmap uses for turns and turnarounds
(:func:`lotsim.roadmap.multipoint.plan_onto`): forward and reverse strokes at the
vehicle's full lock, as many direction changes as :attr:`RouteSettings.max_changes`.

What it reports (:class:`RouteReport`): whether the vehicle makes it and why not, the
path (its segments and poses every :attr:`RouteSettings.step`), its length and direction
changes, the swept envelope (the union of the body's sweeps along the path) and its area,
and the tightest clearance from the body to anything it must keep off, with where and
what that is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Point, Polygon
from shapely.geometry.base import BaseGeometry

from lotsim.core.checks import raise_first, range_problem
from lotsim.core.geometry import FloatArray, Pose, Segment, sample_segments
from lotsim.core.outcome import Outcome, Status
from lotsim.core.units import in_units, shown_area, shown_length
from lotsim.errors import Location
from lotsim.lot.build import obstacle_polygons
from lotsim.lot.clearance import Collider
from lotsim.lot.model import DesignVehicle, Lot, Portal
from lotsim.roadmap.multipoint import plan_onto
from lotsim.vehicles.model import VehicleType

BAYS = ("full", "as_given")
"""What a route assumes of the bays: ``full`` (every bay holds a parked car: what a
designer checks, the default) or ``as_given`` (only the scenario's ``occupied`` bays do;
the others are paved ground the vehicle may drive over)."""

PLACE_KINDS = ("entrance", "exit", "building_entrance", "pose")
"""Where a route starts (an entrance or a pose) and where it must reach (a building
entrance, a pose, or an exit)."""


@dataclass(frozen=True, slots=True)
class RoutePlace:
    """A place a route starts from or must reach.

    Attributes
    ----------
    kind : str
        One of :data:`PLACE_KINDS`.
    id : str
        The entrance's, exit's or building entrance's id ("" for a pose).
    pose : tuple of float or None
        A pose's ``(x [m], y [m], heading [rad])``, or a portal's (None for a building
        entrance).
    point : tuple of float or None
        A building entrance's ``(x, y)`` [m].
    within : float
        For a building entrance: how near [m] the vehicle's body must come to it.
    """

    kind: str
    id: str = ""
    pose: Pose | None = None
    point: tuple[float, float] | None = None
    within: float = 0.0
    where: Location | None = field(default=None, repr=False, compare=False)

    @property
    def name(self) -> str:
        """How messages call it: ``entrance 'west'``, ``(12.0, 3.5)``."""
        if self.kind == "pose" and self.pose is not None:
            return f"({self.pose[0]:g}, {self.pose[1]:g})"
        return f"{self.kind.replace('_', ' ')} {self.id!r}"


@dataclass(frozen=True, slots=True)
class RouteSpec:
    """One route a service vehicle must drive.

    Attributes
    ----------
    id : str
    vehicle : VehicleType
        What drives it (:data:`lotsim.vehicles.catalogue.SERVICE_VEHICLES`, or a car).
    start : RoutePlace
        An entrance, or a pose.
    goal : RoutePlace
        A building entrance, a pose, or an exit.
    leave : tuple of str
        The exits it must then leave by (any one of them); ``()``: it stays.
    bays : str
        One of :data:`BAYS`.
    """

    id: str
    vehicle: VehicleType
    start: RoutePlace
    goal: RoutePlace
    leave: tuple[str, ...] = ()
    bays: str = "full"
    where: Location | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True, slots=True)
class RouteSettings:
    """How routes are planned.

    Attributes
    ----------
    margin : float
        Clearance the path keeps from everything [m] (the body is grown by it).
    max_changes : int
        Most direction changes a leg of a route may have.
    budget : int
        Most states the search of one leg expands.
    tolerance : float
        How far short of or past a pose or an exit [m], along its line and at its
        heading, the vehicle may stop.
    step : float
        Spacing of the reported poses [m]: the envelope is the union of the hulls of
        consecutive footprints.
    """

    margin: float = 0.1
    max_changes: int = 8
    budget: int = 20000
    tolerance: float = 1.0
    step: float = 0.1

    def __post_init__(self) -> None:
        raise_first([(name, p) for name, p in (
            ("margin", range_problem(self.margin, 0.0, 2.0, " m")),
            ("max_changes", range_problem(self.max_changes, 0, 40, integer=True)),
            ("budget", range_problem(self.budget, 1, 10_000_000, integer=True)),
            ("tolerance", range_problem(self.tolerance, 0.5, 20.0, " m")),
            ("step", range_problem(self.step, 0.01, 1.0, " m")),
        ) if p])


@dataclass(frozen=True, slots=True, eq=False)
class RouteReport:
    """What planning a route found.

    Attributes
    ----------
    id, vehicle : str
        The route's id and its vehicle's name.
    status : Status
        ``FOUND`` when the vehicle makes it; else why not in ``reason``.
    reason : str
        Why it fails, in words a designer can act on ("" when it passes).
    segments : tuple of Segment
        The path, every leg one after the other.
    poses : ndarray, shape (N, 3)
        Poses along it every :attr:`RouteSettings.step` or closer.
    envelope : Polygon or None
        The swept envelope: the union of the body's sweeps along the path.
    clearance : float
        The tightest distance [m] from the body anywhere on the path to anything it must
        keep off (nan when it fails).
    clearance_at : tuple of float or None
        The point [m] of what it comes nearest to.
    clearance_to : str
        What that is (``slot 'N3'``, ``the lot boundary``).
    legs : tuple of str
        What each leg reaches (``building entrance 'shop_door'``, ``exit 'west_out'``).
    """

    id: str
    vehicle: str
    status: Status
    reason: str = ""
    segments: tuple[Segment, ...] = ()
    poses: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))
    envelope: BaseGeometry | None = None
    clearance: float = math.nan
    clearance_at: tuple[float, float] | None = None
    clearance_to: str = ""
    legs: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        return self.status is Status.FOUND

    @property
    def length(self) -> float:
        """Path length [m]."""
        return float(sum(s.length for s in self.segments))

    @property
    def changes(self) -> int:
        """Direction changes along the path."""
        gears = [s.gear for s in self.segments if s.length > 1e-9]
        return sum(a != b for a, b in zip(gears, gears[1:], strict=False))

    @property
    def area(self) -> float:
        """The envelope's area [m²] (0 when it fails)."""
        return 0.0 if self.envelope is None else float(self.envelope.area)

    def line(self, units: str = "m") -> str:
        """The route's line in ``lotsim validate``'s summary, lengths and the point in
        ``units`` (the scenario file's)."""
        if not self.passed:
            return f"route {self.id} ({self.vehicle}): fails: {self.reason}"
        x, y = (in_units(c, units) for c in (self.clearance_at or (math.nan, math.nan)))
        return (f"route {self.id} ({self.vehicle}): pass, "
                f"{shown_length(self.length, units, '.1f')}, "
                f"{self.changes} direction change{'s' * (self.changes != 1)}, envelope "
                f"{shown_area(self.area, units)}, tightest clearance "
                f"{shown_length(self.clearance, units, '.2f')} to "
                f"{self.clearance_to} at ({x:.1f}, {y:.1f})")

    def to_json(self) -> dict:
        """The report as plain data (``lotsim validate --json``): the envelope as WKT."""
        return {
            "id": self.id, "vehicle": self.vehicle, "passed": self.passed,
            "status": self.status.value, "reason": self.reason,
            "legs": list(self.legs), "length_m": round(self.length, 3),
            "direction_changes": self.changes, "envelope_area_m2": round(self.area, 3),
            "clearance_m": None if math.isnan(self.clearance) else round(self.clearance, 3),
            "clearance_at": (None if self.clearance_at is None
                             else [round(v, 3) for v in self.clearance_at]),
            "clearance_to": self.clearance_to,
            "envelope_wkt": None if self.envelope is None else self.envelope.wkt,
            "segments": [[*map(float, s.start), s.distance, s.curvature]
                         for s in self.segments],
        }


def kerb_circle(vehicle: VehicleType) -> float:
    """The vehicle's turning circle between kerbs [m]: the diameter the outer front tyre
    draws at full lock (the tyres' outer track taken as the body's width).

    Examples
    --------
    >>> from lotsim.vehicles.catalogue import SERVICE_VEHICLES
    >>> round(kerb_circle(SERVICE_VEHICLES["fire_pump"]), 2)
    16.8
    """
    r = vehicle.min_turning_radius + vehicle.width / 2
    return 2 * math.hypot(r, vehicle.wheelbase)


def plan_routes(lot: Lot, routes: tuple[RouteSpec, ...], settings: RouteSettings | None = None
                ) -> tuple[RouteReport, ...]:
    """:func:`plan_route` of each of ``routes``, in order."""
    return tuple(plan_route(lot, r, settings) for r in routes)


def plan_route(lot: Lot, route: RouteSpec, settings: RouteSettings | None = None
               ) -> RouteReport:
    """Plan ``route`` through ``lot``: from its start to its goal, and out by one of its
    exits if it must leave.

    Every leg is a multi-point path (:func:`lotsim.roadmap.multipoint.plan_onto`) for the
    route's vehicle grown by :attr:`RouteSettings.margin`, on the lot's ground (and, at the
    entrance it starts from and the exits it leaves by, the ground beyond the boundary its
    body needs there), clear of the lot's areas and access aisles and of the bays
    (:data:`BAYS`).

    A route that fails says why in its report (``status`` and ``reason``); a route
    whose places the lot does not hold is refused where it is read (the scenario file).
    """
    settings = settings or RouteSettings()
    v = route.vehicle
    m = settings.margin
    body = DesignVehicle(v.width + 2 * m, v.front + m, v.rear + m, v.min_turning_radius,
                         1.0, 1.0)
    entrances = {p.id: p for p in lot.entrances}
    exits = {p.id: p for p in lot.exits}
    portals = []
    if route.start.kind == "entrance":
        portals.append((entrances[route.start.id], -1))
    if route.goal.kind == "exit":
        portals.append((exits[route.goal.id], 1))
    portals += [(exits[e], 1) for e in route.leave]
    gates = [_gate(p, v, side, lot.boundary) for p, side in portals]
    allowed = shapely.union_all([lot.ground, *gates])
    slots = lot.slots if route.bays == "full" else tuple(
        s for s in lot.slots if s.id in lot.occupied)
    obstacles = obstacle_polygons(lot.areas, slots, lot.access_aisles)
    collider = Collider(obstacles, allowed, edge=lot.edge)

    def failed(reason: str, status: Status = Status.INFEASIBLE) -> RouteReport:
        return RouteReport(route.id, v.name, status, reason)

    start = (route.start.pose if route.start.kind == "pose"
             else entrances[route.start.id].pose)
    hit = collider.first_hit(body.footprints(np.array([start], dtype=float)))
    if hit is not None:
        return failed(f"at its start, {route.start.name}, it touches {hit.what}")
    legs = [(route.goal, _targets(lot, route.goal, v, settings))]
    if route.leave:
        legs.append((RoutePlace("exit", route.leave[0]) if len(route.leave) == 1 else
                     RoutePlace("exit", " or ".join(route.leave)),
                     [(exits[e].pose, -settings.tolerance, settings.tolerance)
                      for e in route.leave]))
    segments: list[Segment] = []
    names = []
    here: Pose = tuple(map(float, start))  # type: ignore[assignment]
    for place, targets in legs:
        if not targets:
            return failed(f"no lane brings its body within {place.within:g} m of "
                          f"{place.name}")
        if place.kind in ("pose", "exit"):
            hit = collider.first_hit(body.footprints(np.array([targets[0][0]], dtype=float)))
            if hit is not None:
                return failed(f"at {place.name} it touches {hit.what}")
        targets = sorted(targets, key=lambda t: math.dist(here[:2], t[0][:2]))
        found = None
        for frame, lo, hi in targets:
            onto = _straight_onto(here, frame, lo, hi, collider, body, settings.step)
            if not onto.found:
                onto = plan_onto([here], frame, lo, hi, collider, body, v.min_turning_radius,
                                 max_changes=settings.max_changes, budget=settings.budget)
            if onto.found:
                found = onto.value
                break
        if found is None:
            return failed(_why_not(lot, here, place, targets, v, settings),
                          Status.NO_PATH)
        segments += found[1]
        names.append(place.name)
        if found[1]:
            end = found[1][-1].end
            here = (float(end[0]), float(end[1]), float(end[2]))
    poses, _ = sample_segments(segments, settings.step)
    prints = v.footprints(poses)
    envelope = sweep_envelope(prints)
    edge = _edge_lines(allowed, gates)
    clearance, at, what = _clearance(envelope, obstacles, edge, collider.edge)
    return RouteReport(route.id, v.name, Status.FOUND, "", tuple(segments), poses, envelope,
                       clearance, at, what, tuple(names))


def _straight_onto(here: Pose, frame: Pose, lo: float, hi: float, collider: Collider,
                   body: DesignVehicle, step: float
                   ) -> Outcome[tuple[int, tuple[Segment, ...]]]:
    """A straight drive forward from ``here`` onto the stretch, when ``here`` lies on its
    line at its heading before it and the way is clear, as
    :func:`~lotsim.roadmap.multipoint.plan_onto` answers (the start's index, 0, and the
    segments); else not found. (The multi-point search lands by a last arc, so it does not
    find the plain straight.)"""
    c, s = math.cos(frame[2]), math.sin(frame[2])
    dx, dy = here[0] - frame[0], here[1] - frame[1]
    along, across = c * dx + s * dy, -s * dx + c * dy
    if abs(across) > 1e-6 or abs(math.remainder(here[2] - frame[2], 2 * math.pi)) > 1e-6:
        return Outcome.failed(Status.NO_PATH, "not on the stretch's line at its heading")
    if along > hi:
        return Outcome.failed(Status.NO_PATH, "past the stretch")
    seg = Segment(here, max(lo, along) - along, 0.0)
    if seg.length < 1e-9:
        return Outcome.of((0, ()))
    poses, _ = sample_segments([seg], step)
    hit = collider.sweep_hit(body.footprints(poses))
    if hit is not None:
        return Outcome.failed(Status.INFEASIBLE, f"the straight touches {hit.what}")
    return Outcome.of((0, (seg,)))


def sweep_envelope(footprints: FloatArray) -> BaseGeometry:
    """The union of the hulls of consecutive footprints (N, 4, 2): the area a body sweeps
    along a path sampled finely (an arc is covered up to its sagitta)."""
    pairs = Collider.sweeps(footprints)
    return shapely.union_all(shapely.convex_hull(shapely.multipoints(pairs)))


def _gate(portal: Portal, v: VehicleType, side: int, boundary: Polygon) -> BaseGeometry:
    """The ground beyond the boundary a body needs at a portal: behind an entrance
    (``side`` -1), ahead of an exit (+1), a body's length and a metre each side."""
    x, y, th = portal.pose
    c, s = math.cos(th), math.sin(th)
    reach = v.length + v.front + v.rear
    x0, x1 = (-reach, v.front) if side < 0 else (-v.rear, reach)
    h = v.width / 2 + 1.0
    rect = Polygon([(x + c * a - s * b, y + s * a + c * b)
                    for a, b in ((x0, -h), (x1, -h), (x1, h), (x0, h))])
    return rect.difference(boundary)


def _edge_lines(allowed: BaseGeometry, gates: list[BaseGeometry]) -> BaseGeometry:
    """The allowed region's edge but where it runs round a gate (the way in and out)."""
    edge = allowed.boundary
    if gates:
        edge = edge.difference(shapely.union_all(gates).buffer(0.05))
    return edge


def _targets(lot: Lot, place: RoutePlace, v: VehicleType, settings: RouteSettings
             ) -> list[tuple[Pose, float, float]]:
    """Where a leg may end, as stretches of lines ``(frame pose, lo, hi)``: it ends on the
    line through the frame, heading along it, ``lo`` to ``hi`` metres along."""
    tol = settings.tolerance
    if place.kind == "pose":
        assert place.pose is not None
        return [(place.pose, -tol, tol)]
    if place.kind == "exit":
        return [(next(p.pose for p in lot.exits if p.id == place.id), -tol, tol)]
    assert place.point is not None
    door = place.point
    out = []
    for lane in lot.lanes:
        for seg in lane.segments:
            if seg.curvature != 0.0 or seg.sharpness != 0.0 or seg.length < 1.0:
                continue
            s = np.arange(0.0, seg.length + 1e-9, 0.5)
            th = seg.start[2]
            poses = np.column_stack([seg.start[0] + s * math.cos(th),
                                     seg.start[1] + s * math.sin(th), np.full_like(s, th)])
            near = shapely.distance(shapely.polygons(v.footprints(poses)), Point(door))
            ok = near <= place.within
            # each run of stations near enough is a stretch to land on
            edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
            for a, b in zip(edges[::2], edges[1::2], strict=True):
                if s[b - 1] - s[a] >= 0.5:
                    out.append((tuple(map(float, seg.start)), float(s[a]), float(s[b - 1])))
    return out  # type: ignore[return-value]


def _why_not(lot: Lot, here: Pose, place: RoutePlace, targets, v: VehicleType,
             settings: RouteSettings) -> str:
    """Why no path reaches ``place`` from ``here``, as a designer reads it."""
    circle = kerb_circle(v)
    kept = f"up to {settings.max_changes} direction changes keeping {settings.margin:g} m clear"
    frames = [t[0] for t in targets]
    turn = min(abs(math.remainder(f[2] - here[2], 2 * math.pi)) for f in frames)
    aisle = _aisle_at(lot, here)
    where = f" in aisle {aisle.id} ({aisle.width:g} m wide)" if aisle is not None else ""
    if turn > math.pi / 2:
        return (f"it cannot turn round{where} to reach {place.name}: no multi-point turn "
                f"with {kept} (its turning circle is {circle:.1f} m between kerbs, its "
                f"body {v.length:.1f} m long)")
    return (f"no path to {place.name} with {kept} within {settings.budget} states (its "
            f"turning circle is {circle:.1f} m between kerbs, its body {v.width:.2f} m wide)")


def _aisle_at(lot: Lot, pose: Pose):
    """The aisle whose centreline passes nearest the pose."""
    p = Point(pose[0], pose[1])
    best = min(lot.aisles.values(), key=lambda a: a.line.distance(p), default=None)
    return best


def _clearance(envelope: BaseGeometry, obstacles: list[tuple[str, BaseGeometry]],
               edge: BaseGeometry, edge_name: str
               ) -> tuple[float, tuple[float, float] | None, str]:
    """The envelope's distance to the nearest obstacle or edge, that one's nearest point
    and what it is."""
    geoms = [g for _, g in obstacles]
    names = [n for n, _ in obstacles]
    if not edge.is_empty:
        geoms.append(edge)
        names.append(edge_name)
    if not geoms:
        return math.inf, None, ""
    d = shapely.distance(envelope, np.array(geoms, dtype=object))
    k = int(np.argmin(d))
    line = shapely.shortest_line(envelope, geoms[k])
    x, y = line.coords[1]
    return float(d[k]), (float(x), float(y)), names[k]
