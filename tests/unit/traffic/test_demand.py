"""Demand through a day: rate profiles, several streams, dwell laws, and the constant-rate
stream as it always was.

The statistical tests draw from fixed seeds, so each gives the same answer every run; their
thresholds are stated where they are used (quantiles of the chi-square distribution and
Kolmogorov's asymptotic critical value), each with a false-alarm rate of 1 % or less had
the seeds been random. Their oracles are computed here by hand (the integral of a profile,
the normal distribution function, the bins' shares), not by the code under test.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from conftest import ONE_AISLE, ROOT, scenario_from_text
from lotsim.traffic.demand import (
    HistogramDwell,
    LognormalDwell,
    StreamSpec,
    TrafficSpec,
    arrivals,
    draw_stream,
)

CHI2_999 = {3: 16.266, 4: 18.467, 5: 20.515}
"""The 0.999 quantiles of the chi-square distribution by degrees of freedom."""
KS_99 = 1.628
"""Kolmogorov's asymptotic critical value of √n·D at the 1 % level (Kolmogorov 1933)."""


def stream_of(traffic: str, seed: int = 0):
    """The scenario ONE_AISLE (entrance ``in``, exit ``out``) with this traffic section."""
    return scenario_from_text(f"{ONE_AISLE}seed: {seed}\ntraffic:\n{traffic}")


def times_of(profile, seeds) -> list[np.ndarray]:
    """The profile's arrival times [h] drawn from each seed."""
    return [profile.draw(np.random.default_rng(s)) / 3600.0 for s in seeds]


def ks_uniform(u: np.ndarray) -> float:
    """√n times the Kolmogorov–Smirnov distance of ``u`` from the uniform law on [0, 1]."""
    u = np.sort(u)
    n = len(u)
    k = np.arange(1, n + 1)
    return math.sqrt(n) * float(max(np.max(k / n - u), np.max(u - (k - 1) / n)))


# -- the number of arrivals ---------------------------------------------------------------------

HOURLY = "  stream: {rate_per_hour: [60, 120, 350, 0, 30], start: 3600}\n"
HOURLY_MEANS = [60, 120, 350, 0, 30]  # each hour's integral of the rate, from 1 h
CURVE = "  stream: {rate_per_hour: [[0, 0], [2, 100], [3, 40]]}\n"
CURVE_MEANS = [25, 75, 70]  # trapezia: (0 + 50) / 2, (50 + 100) / 2, (100 + 40) / 2


@pytest.mark.parametrize(("traffic", "first_hour", "means"), [
    (HOURLY, 1, HOURLY_MEANS), (CURVE, 0, CURVE_MEANS)], ids=["hourly", "curve"])
def test_the_arrivals_each_hour_over_many_seeds_are_poisson_with_the_profiles_integral(
        traffic, first_hour, means):
    profile = stream_of(traffic).traffic.streams[0].rate
    seeds = range(400)
    counts = np.array([np.histogram(t, bins=np.arange(first_hour, first_hour + len(means) + 1))[0]
                       for t in times_of(profile, seeds)])          # (seeds, hours)
    means = np.array(means, dtype=float)
    # no car where the rate is zero, none outside the profile
    assert counts[:, means == 0].sum() == 0
    assert counts.sum() == sum(len(t) for t in times_of(profile, seeds))
    # the totals over the seeds: Poisson with 400 times each hour's integral, so
    # Σ (S − E)² / E over the hours with cars is chi-square with that many degrees of freedom
    total, expected = counts[:, means > 0].sum(axis=0), len(seeds) * means[means > 0]
    chi2 = float(np.sum((total - expected) ** 2 / expected))
    assert chi2 < CHI2_999[len(expected)], (total, expected)
    # and from seed to seed a count varies as a Poisson count does (variance = mean), not
    # fixed: Σ over the 400 seeds of (n − Λ)² / Λ lies between the chi-square(400)
    # quantiles 0.0005 and 0.9995 (313.4 and 499.7), for each hour
    for h in np.flatnonzero(means > 0):
        dispersion = float(np.sum((counts[:, h] - means[h]) ** 2) / means[h])
        assert 313.4 < dispersion < 499.7, (h, dispersion)


def test_a_profile_from_its_start_counts_its_hours_from_there_and_a_count_caps_it():
    sc = stream_of("  stream: {rate_per_hour: [{from_h: 1, to_h: 2, rate_per_hour: 600}], "
                   "start: 1800, count: 50}\n", seed=5)
    cars = arrivals(sc.traffic, sc.seed)
    assert len(cars) == 50  # the process brings about 600: the first 50 of them
    times = [a.time for a in cars]
    assert min(times) >= 5400 and max(times) < 9000 and times == sorted(times)
    uncapped = draw_stream(StreamSpec(None, sc.traffic.streams[0].rate, (("valet", 1.0),),
                                      ("in",)), np.random.default_rng(5))
    assert [a.time for a in uncapped[:50]] == times
    assert len(uncapped) > 500 and uncapped[0].id == "s001"  # padded to the expected 600


# -- the arrival times within a piece -------------------------------------------------------------

def test_the_times_within_each_piece_of_a_piecewise_constant_profile_are_uniform():
    profile = stream_of("  stream:\n    rate_per_hour:\n"
                        "      - {from_h: 0, to_h: 1, rate_per_hour: 60}\n"
                        "      - {from_h: 1, to_h: 3, rate_per_hour: 240}\n"
                        "      - {from_h: 5, to_h: 6, rate_per_hour: 30}\n"
                        ).traffic.streams[0].rate
    pooled = np.concatenate(times_of(profile, range(60)))
    assert not np.any((pooled >= 3) & (pooled < 5))  # the gap between pieces has none
    for a, b in ((0, 1), (1, 3), (5, 6)):
        inside = pooled[(pooled >= a) & (pooled < b)]
        # given their number, a Poisson process's times in a piece of constant rate are
        # independent and uniform over it: pooled over seeds too
        assert len(inside) > 1000
        assert ks_uniform((inside - a) / (b - a)) < KS_99, (a, b)


def test_the_times_along_a_linear_piece_have_a_density_proportional_to_the_rate():
    profile = stream_of("  stream: {rate_per_hour: [[0, 20], [1, 220]]}\n"
                        ).traffic.streams[0].rate
    t = np.concatenate(times_of(profile, range(60)))
    # rate 20 + 200 t: the distribution function is (20 t + 100 t²) / 120 on [0, 1]
    assert ks_uniform((20 * t + 100 * t * t) / 120) < KS_99
    # a uniform law, or a density falling instead of rising, would be far off
    assert ks_uniform(t) > 5 * KS_99


# -- dwell laws ---------------------------------------------------------------------------------

def test_a_lognormal_dwell_has_the_median_and_log_spread_it_was_given():
    sc = stream_of("  stream:\n    rate_per_hour: [3000, 3000, 3000, 3000, 3000, 3000, 3000]\n"
                   "    dwell: {lognormal: {median_min: 25, sigma: 0.8}}\n", seed=2)
    assert sc.traffic.streams[0].dwell == LognormalDwell(median=1500.0, sigma=0.8)
    dwell = np.array([a.dwell for a in arrivals(sc.traffic, sc.seed)])
    n = len(dwell)
    assert n > 19_000
    # the sample median's standard error is σ·median·√(π/2)/√n (the density at the median
    # is 1/(median·σ·√(2π))), that of the standard deviation of ln dwell σ/√(2n): 4 of each
    assert abs(np.median(dwell) - 1500.0) < 4 * 0.8 * 1500.0 * math.sqrt(math.pi / 2 / n)
    assert abs(np.mean(np.log(dwell)) - math.log(1500.0)) < 4 * 0.8 / math.sqrt(n)
    assert abs(np.std(np.log(dwell)) - 0.8) < 4 * 0.8 / math.sqrt(2 * n)


def test_a_clipped_dwell_puts_what_falls_outside_on_the_bounds():
    law = LognormalDwell(median=1500.0, sigma=0.8, clip=(600.0, 3600.0))
    x = law.draw(np.random.default_rng(3), 40_000)
    assert x.min() == 600.0 and x.max() == 3600.0
    def below(t):  # P(dwell < t) for the law before clipping: Φ((ln t − ln median) / σ)
        return 0.5 * (1 + math.erf(math.log(t / 1500.0) / (0.8 * math.sqrt(2))))
    for share, p in ((np.mean(x == 600.0), below(600.0)),
                     (np.mean(x == 3600.0), 1 - below(3600.0))):
        assert abs(share - p) < 4 * math.sqrt(p * (1 - p) / len(x)), (share, p)


def test_a_histogram_dwell_draws_its_bins_by_weight_and_uniformly_within_each():
    sc = stream_of("  stream:\n    count: 20000\n    rate_per_hour: 3600\n"
                   "    dwell: {histogram: {edges_min: [20, 30, 45, 60, 90, 120],\n"
                   "                        weights: [4, 3, 0, 2, 1]}}\n")
    law = sc.traffic.streams[0].dwell
    assert law == HistogramDwell((1200.0, 1800.0, 2700.0, 3600.0, 5400.0, 7200.0),
                                 (4.0, 3.0, 0.0, 2.0, 1.0))
    dwell = np.array([a.dwell for a in arrivals(sc.traffic, sc.seed)]) / 60
    counts = np.histogram(dwell, bins=[20, 30, 45, 60, 90, 120])[0]
    assert counts[2] == 0  # a bin without weight is never drawn
    seen, expected = counts[[0, 1, 3, 4]], len(dwell) * np.array([0.4, 0.3, 0.2, 0.1])
    assert float(np.sum((seen - expected) ** 2 / expected)) < CHI2_999[3]
    for a, b in ((20, 30), (60, 90)):
        inside = dwell[(dwell >= a) & (dwell < b)]
        assert ks_uniform((inside - a) / (b - a)) < KS_99


# -- several streams --------------------------------------------------------------------------

def test_streams_alike_draw_different_cars_and_a_list_of_one_is_the_single_stream():
    one = "{rate_per_hour: [100, 100], mix: {valet: 1}, dwell: [300, 900], prefix: a}"
    single = stream_of(f"  stream: {one}\n", seed=9)
    listed = stream_of(f"  streams: [{one}]\n", seed=9)
    assert arrivals(single.traffic, 9) == arrivals(listed.traffic, 9)
    two = stream_of(f"  streams: [{one}, {one.replace('prefix: a', 'prefix: b')}]\n", seed=9)
    cars = arrivals(two.traffic, 9)
    a = [c.time for c in cars if c.id.startswith("a")]
    b = [c.time for c in cars if c.id.startswith("b")]
    assert a == [c.time for c in arrivals(single.traffic, 9)]
    assert set(a).isdisjoint(b) and abs(len(a) - len(b)) < 100
    # a stream with its own seed draws from it, wherever it stands in the list
    own = stream_of(f"  streams: [{one}, {one.replace('prefix: a', 'prefix: b, seed: 9')}]\n")
    assert [c.time for c in arrivals(own.traffic, 0) if c.id.startswith("b")] == a


def test_the_example_day_has_commuters_shoppers_and_evening_visitors():
    sc = scenario_from_text((ROOT / "scenarios" / "day.yaml").read_text(), "day.yaml")
    assert len(sc.traffic.streams) >= 2
    cars = arrivals(sc.traffic, sc.seed)
    by = {s.prefix: [a for a in cars if a.id.startswith(s.prefix)] for s in sc.traffic.streams}
    assert all(by.values()) and sum(map(len, by.values())) == len(cars)
    assert len({a.id for a in cars}) == len(cars)


# -- the stream at a constant rate, as it always was --------------------------------------------

def today(stream: dict, types: list[str], gates: list[str], seed: int) -> list[tuple]:
    """The constant-rate stream as lotsim has drawn it since it had streams, written out
    again from its description: exponential gaps (scale 1 / (rate per hour / 3600) s), the
    times start + cumsum(gaps) − gaps[0], then the types by weight, the entrances uniformly
    and the dwell uniformly, each in one call in that order; times and dwells rounded to the
    millisecond, ids the prefix and the number padded to the count's digits (at least 2)."""
    rng = np.random.default_rng(stream.get("seed", seed))
    n, start = stream["count"], float(stream.get("start", 0.0))
    gaps = rng.exponential(1.0 / (stream["rate_per_hour"] / 3600.0), size=n)
    times = start + np.cumsum(gaps) - gaps[0]
    mix = stream.get("mix") or {t: 1.0 for t in types}
    weights = np.array(list(mix.values()), dtype=float)
    kinds = rng.choice(len(mix), size=n, p=weights / weights.sum())
    entrances = stream.get("entrances", gates)
    doors = rng.integers(0, len(entrances), size=n)
    dwell = stream.get("dwell")
    if dwell is not None:
        lo, hi = (dwell, dwell) if not isinstance(dwell, list) else dwell
        dwell = rng.uniform(lo, hi, size=n)
    digits = max(2, len(str(n)))
    return [(f"{stream.get('prefix', 's')}{k + 1:0{digits}d}", list(mix)[kinds[k]],
             entrances[doors[k]], round(float(times[k]), 3),
             None if dwell is None else round(float(dwell[k]), 3)) for k in range(n)]


SHIPPED_STREAMS = [p for p in sorted([*ROOT.glob("scenarios/*.yaml"),
                                       *ROOT.glob("scenarios/lots/*.yaml")])
                   if "stream" in (yaml.safe_load(p.read_text()).get("traffic") or {})]


@pytest.mark.parametrize("path", SHIPPED_STREAMS, ids=lambda p: p.stem)
def test_every_shipped_stream_draws_the_cars_it_always_drew(path: Path):
    doc = yaml.safe_load(path.read_text())
    types = [t if isinstance(t, str) else t["name"] for t in doc.get("vehicle_types", ["valet"])]
    gates = [e["id"] for e in doc["lot"]["entrances"]]
    sc = scenario_from_text(path.read_text(), path.name)
    drawn = [(a.id, a.vehicle, a.entrance, a.time, a.dwell)
             for a in arrivals(TrafficSpec(streams=sc.traffic.streams), sc.seed)]
    assert drawn == sorted(today(doc["traffic"]["stream"], types, gates, doc.get("seed", 0)),
                           key=lambda c: (c[3], c[0]))


@pytest.mark.parametrize("stream", [
    {"count": 40, "rate_per_hour": 90, "mix": {"valet": 1, "van": 3}, "entrances": ["in", "in2"],
     "start": 12.5, "dwell": 600, "prefix": "q"},
    {"count": 9, "rate_per_hour": 7, "seed": 123, "dwell": [60, 61]},
    {"count": 1, "rate_per_hour": 1e5 / 3, "entrances": ["in2"]}])
def test_a_constant_rate_stream_of_any_keys_draws_as_it_always_did(stream):
    text = ONE_AISLE.replace(
        "vehicle_types: [valet]", "vehicle_types: [valet, {name: van, width: 2.0, front: 4.2, "
        "rear: 1.0, wheelbase: 3.3, max_steer_deg: 30}]").replace(
        "  exits:", "    - {id: in2, x: 3.0, y: 11.0, heading_deg: 0}\n  exits:")
    inline = yaml.safe_dump({"stream": stream}, default_flow_style=True, width=1000)
    sc = scenario_from_text(f"{text}seed: 17\ntraffic: {inline}")
    drawn = [(a.id, a.vehicle, a.entrance, a.time, a.dwell) for a in arrivals(sc.traffic, 17)]
    assert drawn == sorted(today(stream, ["valet", "van"], ["in", "in2"], 17),
                           key=lambda c: (c[3], c[0]))
