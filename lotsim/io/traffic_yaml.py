"""A scenario's ``traffic`` section → a validated, frozen :class:`TrafficSpec`.

The cars listed one by one, and the streams (``stream``, one, or ``streams``, a list), each
with its arrival rate (a number, or a profile over the day in one of three forms:
:data:`PROFILE_FORMS`) and its dwell law (seconds as before, or a mapping of one of the
kinds in :data:`DWELL_KINDS`). The format is documented in ``docs/scenario.md``.
"""

from __future__ import annotations

from lotsim.errors import ErrorCollector
from lotsim.io.lot_yaml import MAX_ITEMS
from lotsim.io.yamlnodes import YNode, describe
from lotsim.traffic.demand import (
    PATIENCE,
    Arrival,
    DwellLaw,
    HistogramDwell,
    LognormalDwell,
    RateProfile,
    Segment,
    StreamSpec,
    TrafficSpec,
    UniformDwell,
    arrivals,
)

MAX_RATE = 1e6
"""Largest arrival rate a stream may give [vehicles/h]."""
MAX_HOUR = 2400.0
"""Latest hour a rate profile may name, counted from its stream's start [h]."""
MAX_DWELL = 1e7
"""Longest dwell a stream's law may name [s]."""
MAX_SIGMA = 3.0
"""Largest spread of a lognormal dwell (the standard deviation of ln dwell)."""
STREAM_KEYS = ("count", "rate_per_hour", "mix", "entrances", "start", "dwell", "seed",
               "prefix")
"""The keys of a stream."""


def parse_traffic(node: YNode, types: list[str], entrances: list[str]) -> TrafficSpec:
    """Validate the ``traffic`` mapping against the scenario's vehicle types and entrances."""
    f = node.fields(optional=["vehicles", "stream", "streams", "patience"])
    if not {"vehicles", "stream", "streams"} & set(f):
        raise node.error("expected 'vehicles' (a list), 'stream' (a mapping), 'streams' (a "
                         "list of them), or vehicles and streams")
    if "stream" in f and "streams" in f:
        raise f["streams"].error("expected 'stream' (one) or 'streams' (a list), not both")
    if not entrances:
        raise node.error("traffic needs an entrance: the lot has none")

    def vehicle_type(n: YNode) -> str:
        name = n.string()
        if name not in types:
            raise n.error(f"expected a vehicle type of this scenario ({', '.join(types)}), "
                          f"found {name!r}")
        return name

    seen: dict[str, YNode] = {}

    def arrival(n: YNode) -> Arrival:
        v = n.fields(required=["id", "arrival"], optional=["type", "entrance", "dwell"])
        ident = v["id"].ident()
        if ident in seen:
            raise v["id"].error(f"vehicle id {ident!r} is used twice")
        seen[ident] = v["id"]
        return Arrival(
            id=ident,
            vehicle=vehicle_type(v["type"]) if "type" in v else types[0],
            entrance=v["entrance"].string(choices=entrances) if "entrance" in v
            else entrances[0],
            time=v["arrival"].number(min=0, max=1e7),
            dwell=v["dwell"].number(positive=True, max=1e7) if "dwell" in v else None,
            where=n.where,
        )

    errors = ErrorCollector()  # each car, each stream and the patience on their own
    items = (errors.attempt(lambda: f["vehicles"].items(min_len=1, max_len=MAX_ITEMS),
                            default=[]) if "vehicles" in f else [])
    vehicles = [errors.attempt(arrival, n) for n in items]
    if "stream" in f:
        nodes = [f["stream"]]
    elif "streams" in f:
        nodes = errors.attempt(lambda: f["streams"].items(min_len=1, max_len=100), default=[])
    else:
        nodes = []
    parsed = [errors.attempt(parse_stream, n, types, entrances, "streams" in f)
              for n in nodes]
    streams = [p for p in parsed if p is not None]
    patience = (errors.attempt(lambda: f["patience"].number(min=0, max=1e7), default=PATIENCE)
                if "patience" in f else PATIENCE)
    for k, (s, where) in enumerate(streams):
        for t, _ in streams[:k]:
            if _may_clash(s.prefix, t.prefix):
                errors.attempt(_refuse, where, f"stream prefix {s.prefix!r} may give the same "
                               f"ids as the prefix {t.prefix!r} of a stream before it "
                               f"({t.where}); give each stream a prefix that no other "
                               "begins, followed by digits")
        for ident, n in seen.items():
            if _may_clash(ident, s.prefix):
                errors.attempt(_refuse, n, f"vehicle id {ident!r} may clash with the stream's "
                               f"ids ({s.prefix}01, ...); pick another id or stream prefix")
    errors.check()
    return TrafficSpec(vehicles=tuple(vehicles), streams=tuple(s for s, _ in streams),
                       patience=patience, where=node.where)


def _refuse(node: YNode, message: str) -> None:
    raise node.error(message)


def _may_clash(ident: str, prefix: str) -> bool:
    """Whether ``ident`` (an id, or another stream's prefix) is ``prefix`` followed by
    nothing but digits, so that the stream may draw it."""
    return ident.startswith(prefix) and (ident[len(prefix):].isdigit()
                                         or ident == prefix)


def parse_stream(node: YNode, types: list[str], entrances: list[str],
                 one_of_several: bool = False) -> tuple[StreamSpec, YNode]:
    """A stream, and where its prefix is given (the stream itself without one): an item of
    ``streams`` (``one_of_several``) must name its prefix."""
    f = node.fields(required=["rate_per_hour", *(["prefix"] if one_of_several else [])],
                    optional=[k for k in STREAM_KEYS if k not in ("rate_per_hour", "prefix")]
                    + ([] if one_of_several else ["prefix"]))
    errors = ErrorCollector()  # each key on its own
    if "mix" in f:
        mix = errors.attempt(_mix, f["mix"], types, default=())
    else:
        mix = tuple((t, 1.0) for t in types)
    gates = (errors.attempt(lambda: tuple(n.string(choices=entrances)
                                          for n in f["entrances"].items(min_len=1)))
             if "entrances" in f else tuple(entrances))
    start = (errors.attempt(lambda: f["start"].number(min=0, max=1e7), default=0.0)
             if "start" in f else 0.0)
    rate = errors.attempt(parse_rate, f["rate_per_hour"], start)
    count = (errors.attempt(lambda: f["count"].integer(min=1, max=MAX_ITEMS))
             if "count" in f else None)
    if "count" not in f and isinstance(rate, float):
        errors.attempt(_refuse, node, "missing key 'count': a stream at a constant "
                       "rate_per_hour needs how many cars come (or give rate_per_hour as a "
                       "profile over the day: a list)")
    dwell = errors.attempt(parse_dwell_law, f["dwell"]) if "dwell" in f else None
    seed = (errors.attempt(lambda: f["seed"].integer(min=0, max=2**63 - 1))
            if "seed" in f else None)
    prefix = errors.attempt(f["prefix"].ident, default="s") if "prefix" in f else "s"
    errors.check()
    spec = StreamSpec(count=count, rate=rate, mix=mix, entrances=gates, start=start,
                      dwell=dwell, seed=seed, prefix=prefix, where=node.where)
    return spec, f.get("prefix", node)


def _mix(node: YNode, types: list[str]) -> tuple[tuple[str, float], ...]:
    m = node.fields(optional=types)
    if not m:
        raise node.error("expected at least one vehicle type with a weight")
    return tuple((k, n.number(positive=True, max=1e6)) for k, n in m.items())


# -- rates over the day -----------------------------------------------------------------------


def _hourly(items: list[YNode], start: float) -> list[Segment]:
    """``[60, 120, 350]``: one rate [vehicles/h] for each hour from the stream's start."""
    if len(items) > MAX_HOUR:
        raise items[0].error(f"expected at most {MAX_HOUR:g} hours of rates, found "
                             f"{len(items)}")
    rates = [n.number(min=0, max=MAX_RATE) / 3600.0 for n in items]
    return [(start + 3600.0 * k, start + 3600.0 * (k + 1), r, r) for k, r in enumerate(rates)]


def _pieces(items: list[YNode], start: float) -> list[Segment]:
    """``[{from_h: 7, to_h: 9, rate_per_hour: 120}, ...]``: a constant rate over each
    piece, in time order (gaps between pieces have none)."""
    out: list[Segment] = []
    end = None
    for n in items:
        p = n.fields(required=["from_h", "to_h", "rate_per_hour"])
        t0 = p["from_h"].number(min=0, max=MAX_HOUR, what="a time in hours")
        if end is not None and t0 < end:
            raise p["from_h"].error(f"expected an hour ≥ {end:g}, where the piece before "
                                    f"ends (pieces in time order, not overlapping), found "
                                    f"{t0:g}")
        t1 = p["to_h"].number(min=0, max=MAX_HOUR, what="a time in hours")
        if t1 <= t0:
            raise p["to_h"].error(f"expected an hour after from_h ({t0:g}), found {t1:g}")
        r = p["rate_per_hour"].number(min=0, max=MAX_RATE) / 3600.0
        out.append((start + 3600.0 * t0, start + 3600.0 * t1, r, r))
        end = t1
    return out


def _curve(items: list[YNode], start: float) -> list[Segment]:
    """``[[6, 0], [8, 300], [10, 60]]``: points ``[hour, rate]``, the rate linear between
    them and zero before the first and after the last."""
    if len(items) < 2:
        raise items[0].error("expected at least 2 points [hour, rate_per_hour] of the curve, "
                             "found 1")
    points: list[tuple[float, float]] = []
    for n in items:
        h, r = n.items(min_len=2, max_len=2)
        hour = h.number(min=0, max=MAX_HOUR, what="a time in hours")
        if points and hour <= points[-1][0]:
            raise h.error(f"expected an hour after {points[-1][0]:g} (the point before: "
                          f"points in time order), found {hour:g}")
        points.append((hour, r.number(min=0, max=MAX_RATE) / 3600.0))
    return [(start + 3600.0 * h0, start + 3600.0 * h1, r0, r1)
            for (h0, r0), (h1, r1) in zip(points, points[1:], strict=False)]


PROFILE_FORMS = {"hourly": _hourly, "pieces": _pieces, "curve": _curve}
"""The forms of a rate profile, by what its list holds: numbers (a rate for each hour),
mappings (pieces ``{from_h, to_h, rate_per_hour}``) or lists (points ``[hour, rate]``)."""
_FORM_ITEM = {"hourly": "a number (a rate for each hour)",
              "pieces": "a mapping {from_h, to_h, rate_per_hour}",
              "curve": "a point [hour, rate_per_hour]"}


def parse_rate(node: YNode, start: float) -> float | RateProfile:
    """A stream's ``rate_per_hour``: a number, a constant rate [1/s]; or a list, a rate
    profile (:data:`PROFILE_FORMS`) whose hours count from ``start`` [s]."""
    if not node.is_sequence:
        return node.number(positive=True, max=MAX_RATE) / 3600.0
    items = node.items(min_len=1, max_len=MAX_ITEMS)
    def form_of(n: YNode) -> str:
        return "pieces" if n.is_mapping else "curve" if n.is_sequence else "hourly"

    form = form_of(items[0])
    for n in items[1:]:
        if form_of(n) != form:
            raise n.error(f"expected {_FORM_ITEM[form]}, as the first item of the profile, "
                          f"found {describe(n.node)}")
    profile = RateProfile(tuple(PROFILE_FORMS[form](items, start)))
    total = profile.expected()
    if not total > 0:
        raise node.error("expected a profile with a positive rate somewhere: this one "
                         "brings no car")
    if total > MAX_ITEMS:
        raise node.error(f"expected a profile bringing at most {MAX_ITEMS} cars, found one "
                         f"bringing {total:.0f} on average")
    return profile


# -- dwell laws -------------------------------------------------------------------------------


def parse_dwell(d: YNode) -> tuple[float, float]:
    """A dwell in seconds: one number or ``[min, max]``, as (min, max)."""
    if d.is_sequence:
        lo, hi = (n.number(positive=True, max=MAX_DWELL) for n in d.items(min_len=2,
                                                                          max_len=2))
        if hi < lo:
            raise d.error(f"expected [min, max] with min <= max, found [{lo:g}, {hi:g}]")
        return lo, hi
    x = d.number(positive=True, max=MAX_DWELL)
    return x, x


def _minutes(n: YNode, *, positive: bool = False) -> float:
    """A time in minutes, as seconds."""
    return 60.0 * n.number(positive=positive, min=0, max=MAX_DWELL / 60,
                           what="a time in minutes")


def _clip(node: YNode) -> tuple[float, float]:
    """``clip_min: [min, max]`` in minutes, as seconds."""
    lo, hi = (_minutes(n) for n in node.items(min_len=2, max_len=2))
    if hi < lo:
        raise node.error(f"expected [min, max] with min <= max, found [{lo / 60:g}, "
                         f"{hi / 60:g}]")
    return lo, hi


def _uniform(node: YNode, clip: tuple[float, float] | None) -> UniformDwell:
    f = node.fields(required=["low_min", "high_min"])
    low, high = _minutes(f["low_min"], positive=True), _minutes(f["high_min"], positive=True)
    if high < low:
        raise f["high_min"].error(f"expected at least low_min ({low / 60:g}), found "
                                  f"{high / 60:g}")
    return UniformDwell(low, high, clip)


def _lognormal(node: YNode, clip: tuple[float, float] | None) -> LognormalDwell:
    f = node.fields(required=["median_min", "sigma"])
    return LognormalDwell(_minutes(f["median_min"], positive=True),
                          f["sigma"].number(positive=True, max=MAX_SIGMA), clip)


def _histogram(node: YNode, clip: tuple[float, float] | None) -> HistogramDwell:
    f = node.fields(required=["edges_min", "weights"])
    edges: list[float] = []
    for n in f["edges_min"].items(min_len=2, max_len=1000):
        e = _minutes(n)
        if edges and e <= edges[-1]:
            raise n.error(f"expected an edge after {edges[-1] / 60:g} (edges in increasing "
                          f"order), found {e / 60:g}")
        edges.append(e)
    k = len(edges) - 1
    wn = f["weights"]
    if wn.is_sequence and len(wn.node.value) != k:
        raise wn.error(f"expected {k} weights, one for each bin between the {k + 1} edges, "
                       f"found {len(wn.node.value)}")
    weights = tuple(n.number(min=0, max=1e9) for n in wn.items(min_len=k, max_len=k))
    if not sum(weights) > 0:
        raise wn.error("expected a positive weight for some bin")
    return HistogramDwell(tuple(edges), weights, clip)


DWELL_KINDS = {"uniform": _uniform, "lognormal": _lognormal, "histogram": _histogram}
"""The laws a stream's dwell is drawn from, by the key that names them (times in minutes)."""


def parse_dwell_law(node: YNode) -> DwellLaw:
    """A stream's ``dwell``: seconds, one number or ``[min, max]`` (uniform); or a mapping
    of one of :data:`DWELL_KINDS`, optionally ``clip_min: [min, max]``."""
    if not node.is_mapping:
        return UniformDwell(*parse_dwell(node))
    f = node.fields(optional=[*DWELL_KINDS, "clip_min"])
    kinds = [k for k in DWELL_KINDS if k in f]
    if len(kinds) != 1:
        found = f", found {' and '.join(kinds)}" if kinds else ""
        raise node.error(f"expected one of {', '.join(DWELL_KINDS)} (the law dwell times are "
                         f"drawn from){found}")
    clip = _clip(f["clip_min"]) if "clip_min" in f else None
    return DWELL_KINDS[kinds[0]](f[kinds[0]], clip)


def traffic_ids(traffic: TrafficSpec, seed: int) -> set[str]:
    """Every car id of ``traffic``: those listed and those its streams draw with the
    scenario's ``seed`` (a stream of a profile draws more or fewer cars with another)."""
    return {a.id for a in arrivals(traffic, seed)}
