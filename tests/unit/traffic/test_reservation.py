"""The reservation table never lets two bodies touch at any instant (checked densely)."""

import math

import numpy as np
import pytest
import shapely
import shapely.affinity
from shapely.geometry import box

from lotsim.core.geometry import Segment
from lotsim.traffic import candidates
from lotsim.traffic.grid import CELL, cells_of, cells_of_all
from lotsim.traffic.reservation import ReservationTable
from lotsim.traffic.search import _free_till
from lotsim.traffic.swept import Swept, standing_body, swept, swept_motion, swept_motions
from lotsim.vehicles import CATALOGUE
from lotsim.vehicles.motion import Piece, drive, timed_path

CAR = CATALOGUE["valet"]


def _random_pieces(rng):
    x, y = rng.uniform(-10, 10, size=2)
    th = rng.uniform(-np.pi, np.pi)
    pieces, pose = [], (float(x), float(y), float(th))
    for _ in range(rng.integers(1, 4)):
        seg = Segment(pose, float(rng.uniform(2, 12)) * rng.choice([1, 1, -1]),
                      float(rng.uniform(-1, 1) * CAR.max_curvature))
        pieces.append(Piece(seg))
        pose = seg.end
    return pieces


def _dense_overlap(a, b):
    """Whether the two vehicles' footprints overlap at some common instant (every 10 ms),
    with the poses computed on the exact path (not interpolated)."""
    lo, hi = max(a.start_time, b.start_time), min(a.end_time, b.end_time)
    if hi <= lo:
        return False
    t = np.arange(lo, hi, 0.01)

    def at(tr):
        th = np.interp(t, tr.t, np.unwrap(tr.theta))
        return CAR.footprints(np.column_stack([np.interp(t, tr.t, tr.x),
                                               np.interp(t, tr.t, tr.y), th]))

    return bool(shapely.intersects(shapely.polygons(at(a)), shapely.polygons(at(b))).any())


@pytest.mark.slow
@pytest.mark.parametrize("via", ["motion", "trajectory"])
def test_random_crossings_that_touch_at_an_instant_are_always_caught(via):
    rng = np.random.default_rng(11)
    caught = touching = 0
    for _ in range(150):
        pa, pb = _random_pieces(rng), _random_pieces(rng)
        ta, tb = float(rng.uniform(0, 3)), float(rng.uniform(0, 3))
        # the dense reference drives the paths sampled every 2 ms
        a, b = drive(pa, CAR, t0=ta, dt=0.002), drive(pb, CAR, t0=tb, dt=0.002)
        table = ReservationTable()
        if via == "motion":
            table.reserve("a", swept_motion(timed_path(pa, CAR), CAR), offset=ta)
            conflict = table.first_conflict(swept_motion(timed_path(pb, CAR), CAR),
                                            offset=tb)
        else:  # sampled trajectories, chunk edges missing from their samples
            ra, rb = drive(pa, CAR, t0=ta), drive(pb, CAR, t0=tb)
            table.reserve("a", swept(ra.poses, ra.t, CAR))
            conflict = table.first_conflict(swept(rb.poses, rb.t, CAR))
        if _dense_overlap(a, b):
            touching += 1
            assert conflict is not None and conflict.owner == "a"
        caught += conflict is not None
    assert touching >= 10  # the sample exercises real clashes
    assert caught >= touching


def test_hulls_cover_the_exact_footprints_of_a_tight_turn():
    arc = Segment((0.0, 0.0, 0.3), 12.0, CAR.max_curvature)
    hulls = swept_motion(timed_path([Piece(arc)], CAR), CAR)
    union = shapely.union_all([h for _, _, h in hulls])
    exact = shapely.polygons(CAR.footprints(arc.sample(0.005)))
    assert shapely.covers(union.buffer(0.005), exact).all()
    assert max(t1 - t0 for t0, t1, _ in hulls) <= 0.5 + 1e-9


def test_a_parked_car_blocks_only_from_when_it_parks_and_not_its_owner():
    table = ReservationTable()
    table.reserve_standing("p", box(0, 0, 2, 5), since=10.0)
    probe = box(1, 1, 3, 3)
    assert table.is_free([(5.0, 9.5, probe)])
    assert table.first_conflict([(9.0, 10.5, probe)]).owner == "p"
    assert table.is_free([(200.0, 201.0, probe)], ignore="p")
    assert table.taken_until(probe) == math.inf and table.taken_until(probe, ignore="p") < 0
    assert table.taken_until(box(5, 5, 6, 6)) == -math.inf


def test_release_after_a_time_keeps_the_past_and_cuts_the_parked_car_there():
    table = ReservationTable()
    motion = timed_path([Piece(Segment((0.0, 0.0, 0.0), 10.0, 0.0))], CAR)
    table.reserve("v", swept_motion(motion, CAR))
    end = standing_body(CAR, (10.0, 0.0, 0.0))
    table.reserve_standing("v", end, since=motion.duration)
    late = [(motion.duration + 5, motion.duration + 6, end)]
    assert not table.is_free(late)
    table.release("v", after=motion.duration + 3)
    assert table.is_free(late)
    assert not table.is_free([(motion.duration + 1, motion.duration + 2, end)])
    assert not table.is_free([(0.0, 0.1, standing_body(CAR, (0.0, 0.0, 0.0)))])
    table.release("v")
    assert len(table) == 0


def test_long_and_short_entries_are_both_found_across_many_buckets():
    table = ReservationTable(bucket=1.0)
    table.reserve_standing("long", box(0, 0, 1, 1), since=3.0, until=500.0)
    table.reserve("short", [(40.0, 40.5, box(10, 0, 11, 1))])
    assert table.first_conflict([(499.0, 499.5, box(0.5, 0.5, 2, 2))]).owner == "long"
    assert table.is_free([(500.5, 501.0, box(0.5, 0.5, 2, 2))])
    assert table.first_conflict([(39.0, 40.0, box(10.5, 0, 12, 1))]).owner == "short"
    assert table.is_free([(41.0, 42.0, box(10.5, 0, 12, 1))])


def test_bad_bucket_is_refused():
    with pytest.raises(ValueError):
        ReservationTable(bucket=0)


def test_releases_are_recorded_only_when_they_free_space():
    table = ReservationTable()
    table.reserve("a", [(0.0, 2.0, box(0, 0, 1, 1)), (2.0, 4.0, box(1, 0, 2, 1))])
    table.release("a", after=5.0)  # nothing begins or runs past 5 s
    table.release("nobody")
    assert table.releases == []
    table.release("a", after=3.0)  # cuts the second short
    table.release("a", after=1.0)  # drops it, cuts the first
    table.release("a")
    table.reserve_standing("b", box(5, 0, 7, 2), 0.0, in_slot=True)
    table.release("b", after=9.0)
    assert table.releases == [(3.0, "a", False), (1.0, "a", False), (-math.inf, "a", False),
                              (9.0, "b", True)]
    assert len(table) == 1


def test_blocked_departures_are_exactly_the_offsets_is_free_refuses():
    # random motions against random bodies held over random times (some for ever): a
    # departure the table calls free lies outside every blocked interval, and one it does
    # not lies inside one, at random offsets and at each interval's very ends
    rng = np.random.default_rng(5)
    for _ in range(25):
        table = ReservationTable()
        for k in range(12):
            x, y = rng.uniform(-12, 12, size=2)
            t0 = float(rng.uniform(0, 30))
            body = box(x, y, x + rng.uniform(0.3, 3), y + rng.uniform(0.3, 3))
            if k == 0:
                table.reserve_standing("wall", body, t0)
            else:
                table.reserve(f"o{k}", [(t0, t0 + float(rng.uniform(0.2, 8)), body)])
        motion = timed_path(_random_pieces(rng), CAR)
        sw = Swept.of(swept_motion(motion, CAR))
        hit = table.blocked(sw, 0.0, 40.0)
        assert all(a[1] < b[0] for a, b in zip(hit, hit[1:], strict=False))  # disjoint
        probes = list(rng.uniform(0, 40, size=40))
        probes += [t for lo, hi in hit for t in (lo + 1e-7, hi - 1e-7, lo - 1e-6, hi + 1e-6)
                   if 0 <= t <= 40]
        for d in probes:
            inside = any(lo <= d <= hi for lo, hi in hit)
            assert table.is_free(sw, offset=float(d)) is not inside, (d, hit)


def _random_table(rng, n=40, few=True):
    """Bodies held by a few owners over random times: short ones, ones spanning many time
    buckets, some for ever, some standing in a slot. Times on a 0.5 s grid and corners on
    a 1 m one, so that bodies and times often just touch. Not ``few``: its queries take
    numpy's way for any number of candidates, not Python's."""
    table = ReservationTable() if few else ReservationTable(few_pairs=0, few_entries=0)
    for k in range(n):
        x, y = rng.integers(-15, 15, size=2)
        body = box(x, y, x + rng.integers(1, 5), y + rng.integers(1, 5))
        t0 = float(rng.integers(0, 120)) / 2
        kind = rng.integers(6)
        if kind == 0:
            table.reserve_standing(f"o{k % 5}", body, t0, in_slot=bool(rng.integers(2)))
        elif kind == 1:
            table.reserve_standing(f"o{k % 5}", body, t0, t0 + float(rng.integers(40, 180)) / 2)
        else:
            table.reserve(f"o{k % 5}", [(t0, t0 + float(rng.integers(1, 6)) / 2, body)])
    if rng.integers(2):
        table.release("o1", after=float(rng.integers(0, 120)) / 2)
    return table


def _random_swept(rng):
    x, y = rng.integers(-15, 15, size=2)
    out, t = [], 0.0
    for _ in range(rng.integers(1, 8)):
        dt = float(rng.integers(0, 2)) / 2
        out.append((t, t + dt, box(x, y, x + rng.integers(1, 3), y + rng.integers(1, 3))))
        t += dt
        x, y = x + rng.integers(-3, 4), y + rng.integers(-3, 4)
    return Swept.of(out)


def _brute_first_conflict(table, sw, offset, ignore):
    """The earliest interval's clash, entry by entry in the order they were reserved (an
    independent reading of the store: alive, not ``ignore``'s, not in a slot)."""
    st = table._store
    skip = st.ids.get(ignore, -1)
    for (a, z), g in zip(sw.t, sw.geoms, strict=True):
        a, z = a + offset, z + offset
        for i in range(st.n):
            if (st.alive[i] and not st.in_slot[i] and st.owner[i] != skip
                    and st.t[i, 0] <= z + 1e-9 and st.t[i, 1] >= a - 1e-9
                    and shapely.intersects(g, st.geom[i])):
                return st.names[st.owner[i]], float(st.t[i, 0]), float(st.t[i, 1])
    return None


@pytest.mark.slow
@pytest.mark.parametrize("few", [True, False])
def test_queries_among_the_nearby_entries_answer_as_the_table_and_a_brute_force_do(few):
    # candidates gathered once over the cells and times of several queries (as a search
    # does per edge) are every entry that may meet them (read off the store directly), and
    # give the same first conflicts (also found by brute force) and the same blocked
    # departures as the queries gathering their own; long windows (more time buckets
    # than a cell holds) included
    rng = np.random.default_rng(16)
    clashes = blocked = 0
    for _ in range(80):
        table = _random_table(rng, n=int(rng.choice([40, 300])), few=few)
        st = table._store
        sws = [_random_swept(rng) for _ in range(3)]
        ignore = "o2" if rng.integers(2) else None
        since = float(rng.integers(0, 120)) / 2
        until = since + float(rng.choice([0, rng.integers(0, 10), rng.integers(100, 7200)])) / 2
        longest = max(float(sw.t[:, 1].max()) for sw in sws)
        b = np.vstack([sw.bounds for sw in sws])
        cells = cells_of((b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()))
        near = table.nearby(cells, since, until + longest, ignore=ignore)
        want = [i for i in range(st.n)
                if st.alive[i] and not st.in_slot[i] and st.owner[i] != st.ids.get(ignore)
                and st.t[i, 0] <= until + longest + 1e-9 and st.t[i, 1] >= since - 1e-9
                and set(cells_of(st.box[i])) & set(cells)]
        assert near.ids == want
        assert near.rows == [(*st.t[i], *st.box[i]) for i in want]
        # only those whose box meets the box of all the queries' hulls: the same answers
        inside = table.nearby(cells, since, until + longest, ignore=ignore,
                              box=(*b[:, :2].min(axis=0), *b[:, 2:].max(axis=0)))
        assert set(inside.ids) <= set(near.ids)
        assert near.within((*b[:, :2].min(axis=0), *b[:, 2:].max(axis=0))) == inside
        # kept in a memo (as a search keeps it): the same answers, asked first or again, and
        # for other windows over the same time buckets (the exact times compared each time)
        memo: dict = {}
        for late in (0.0, 0.0, 0.25, 0.5, 0.75):
            t0, t1 = since + late, until + longest - late
            for bx in (None, (*b[:, :2].min(axis=0), *b[:, 2:].max(axis=0))):
                assert (table.nearby(tuple(cells), t0, t1, ignore=ignore, box=bx, memo=memo)
                        == table.nearby(cells, t0, t1, ignore=ignore, box=bx))
        for sw in sws:
            for d in (since, float(rng.integers(2 * since, 2 * until + 1)) / 2):
                got = table.first_conflict(sw, offset=d, ignore=ignore, among=near)
                assert table.first_conflict(sw, offset=d, ignore=ignore) == got
                assert table.first_conflict(sw, offset=d, ignore=ignore, among=inside) == got
                assert table.is_free(sw, offset=d, ignore=ignore, among=near) == (got is None)
                pairs = candidates.pairs(sw, near, d, few=table.few_pairs)
                anyhow = candidates.pairs(sw, near, d, ordered=False, few=table.few_pairs)
                assert sorted(zip(*pairs, strict=True)) == list(zip(*pairs, strict=True))
                assert sorted(zip(*anyhow, strict=True)) == list(zip(*pairs, strict=True))
                assert table.is_free(sw, offset=d, ignore=ignore, among=inside) == (got is None)
                assert ((None if got is None else (got.owner, got.t0, got.t1))
                        == _brute_first_conflict(table, sw, d, ignore))
                clashes += got is not None
            hit = table.blocked(sw, since, until, ignore=ignore, among=near)
            assert hit == table.blocked(sw, since, until, ignore=ignore)
            assert hit == table.blocked(sw, since, until, ignore=ignore, among=inside)
            blocked += bool(hit)
    assert clashes >= 40 and blocked >= 40  # the sample exercises real clashes


def test_a_table_that_forgets_the_past_answers_every_later_query_as_one_that_keeps_it():
    # the same random table twice, one told the clock has reached ``now`` (in one step or
    # two): queries from ``now`` on (as a search starting then makes) get the same answers,
    # releases from then on are recorded alike; and the past is really gone
    rng = np.random.default_rng(28)
    forgot = 0
    for _ in range(60):
        seed = int(rng.integers(1 << 30))
        kept, table = (_random_table(np.random.default_rng(seed), n=120) for _ in range(2))
        now = float(rng.integers(0, 120)) / 2
        if rng.integers(2):
            table.forget_before(now - float(rng.integers(1, 20)) / 2)
        table.forget_before(now)
        st = table._store
        forgot += sum(r is None for r in st.rows) - sum(r is None for r in kept._store.rows)
        assert all(k >= math.floor((now - 1e-9) / table.bucket)
                   for c in table._grid.by_cell.values() for k in c)
        for _ in range(6):
            sw = _random_swept(rng)
            ignore = "o2" if rng.integers(2) else None
            since = now + float(rng.choice([0, rng.integers(0, 20)])) / 2  # often now
            until = since + float(rng.choice([0, rng.integers(0, 10), rng.integers(100, 400)]))
            cells = sorted({c for cs in sw.cells for c in cs})
            longest = float(sw.t[:, 1].max())
            near = table.nearby(cells, since, until + longest, ignore=ignore)
            assert near == kept.nearby(cells, since, until + longest, ignore=ignore)
            assert (table.blocked(sw, since, until, ignore=ignore)
                    == kept.blocked(sw, since, until, ignore=ignore)
                    == table.blocked(sw, since, until, ignore=ignore, among=near))
            for d in (since, min(until, since + float(rng.integers(0, 10)) / 2)):
                got = table.first_conflict(sw, offset=d, ignore=ignore)
                assert got == kept.first_conflict(sw, offset=d, ignore=ignore)
                assert got == table.first_conflict(sw, offset=d, ignore=ignore, among=near)
            body = sw.geoms[0]
            a, b = (x.taken_until(body, ignore=ignore) for x in (table, kept))
            assert a == b or (a < now and b < now)  # compared only with times from now on
        after = now + float(rng.integers(0, 10)) / 2
        for x in (table, kept):
            x.release("o3", after=after)
        assert table.releases == kept.releases
    assert forgot > 1000  # the past is dropped, not only never read


def test_standing_bodies_kept_between_queries_are_blocked_as_the_table_says():
    # bodies asked about again and again while the table grows, drops, cuts short and
    # forgets entries (as lane nodes are by one search after another): each query gives
    # the intervals blocked gives, and one made anew (nothing kept) gives them too
    rng = np.random.default_rng(30)
    met = 0
    for _ in range(40):
        table = _random_table(rng, n=int(rng.choice([20, 120])))
        bodies = []
        for _ in range(4):
            x, y = rng.integers(-15, 15, size=2)
            body = box(x, y, x + rng.integers(1, 4), y + rng.integers(1, 4))
            bodies.append(Swept.of([(0.0, 0.0, body)]))
        now = 0.0
        for step in range(12):
            kind = rng.integers(4)
            if kind == 0:  # more reserved (some long, some in a slot)
                more = _random_table(rng, n=10)._store
                for i in range(more.n):
                    t0, t1 = more.t[i]
                    if more.in_slot[i] or math.isinf(t1):
                        table.reserve_standing(f"o{i % 5}", more.geom[i], now + t0,
                                               in_slot=bool(more.in_slot[i]))
                    else:
                        table.reserve(f"o{i % 5}", [(now + t0, now + t1, more.geom[i])])
            elif kind == 1:
                table.release(f"o{rng.integers(5)}", after=now + float(rng.integers(0, 60)) / 2)
            elif kind == 2:
                now += float(rng.integers(0, 20)) / 2
                table.forget_before(now)
            ignore = f"o{rng.integers(5)}" if rng.integers(2) else None
            since = now + float(rng.integers(0, 10)) / 2
            until = since + float(rng.choice([0, rng.integers(0, 20), rng.integers(100, 3600)]))
            for sw in bodies:
                want = table.blocked(sw, since, until, ignore=ignore)
                assert table.blocked_standing(sw, since, until, ignore=ignore) == want, step
                fresh = Swept(sw.geoms, sw.cells, sw.rows)  # another object: nothing kept
                assert table.blocked_standing(fresh, since, until, ignore=ignore) == want
                met += bool(want)
    assert met > 300  # the sample meets bodies often


def test_motions_swept_together_are_swept_as_each_alone():
    # one straight path (one or several collinear segments) driven between random speeds,
    # swept together: the very same hulls, times, boxes and cells as one by one; curved
    # paths and mixed groups fall back to one by one
    from lotsim.vehicles.motion import Motion, Stroke, scurve

    rng = np.random.default_rng(3)
    lim = CAR.limits
    top = lim.max_forward_speed
    for trial in range(40):
        x, y, th = rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-np.pi, np.pi)
        kappa = 0.0 if trial % 4 else float(rng.uniform(-0.1, 0.1))
        path, pose = [], (float(x), float(y), float(th))
        for _ in range(rng.integers(1, 4)):
            seg = Segment(pose, float(rng.uniform(0.3, 9)), kappa)
            path.append(seg)
            pose = seg.end
        length = sum(g.length for g in path)
        motions = []
        for _ in range(rng.integers(1, 6)):
            v0, v1 = rng.uniform(0, top, size=2)
            prof = scurve(length, float(v0), float(v1), top, lim.max_accel, lim.max_brake,
                          lim.max_jerk)
            if prof is not None:
                motions.append(Motion((Stroke(tuple(path), prof),)))
        if not motions:
            continue
        together = swept_motions(motions, CAR)
        for m, sw in zip(motions, together, strict=True):
            intervals = swept_motion(m, CAR)
            alone = Swept.of(intervals)
            assert np.array_equal(sw.t, alone.t) and np.array_equal(sw.bounds, alone.bounds)
            # the arrays made from the rows: the intervals' times and shapely's bounds
            assert np.array_equal(sw.t, [(a, z) for a, z, _ in intervals])
            assert np.array_equal(sw.bounds, shapely.bounds(sw.geoms))
            assert sw.cells == alone.cells and sw.rows == alone.rows
            assert all(shapely.equals_exact(a, b, tolerance=0.0)
                       for a, b in zip(sw.geoms, alone.geoms, strict=True))


def test_when_a_standing_body_is_first_in_the_way_can_be_read_from_one_query():
    # a search asks once per node, from its start t0, when a body standing there is in
    # somebody's way, and reads from that when it is first in the way after any later t:
    # the same time as a query from t on, or (both) before t: in the way already
    rng = np.random.default_rng(7)
    later = before = 0
    for _ in range(30):
        table = _random_table(rng, n=60)
        x, y = rng.integers(-15, 15, size=2)
        stand = Swept.of([(0.0, 0.0, box(x, y, x + 2, y + 4))])
        t0, end = float(rng.integers(0, 40)) / 2, 100.0
        once = table.blocked(stand, t0, end, ignore="o3")
        for t in [t0 + float(k) / 2 for k in range(0, 80)]:
            mine = _free_till(once, t)
            # from t on: the first stretch of departures from t that are in the way
            own = min((lo for lo, hi in table.blocked(stand, t, end, ignore="o3")
                       if hi >= t), default=math.inf)
            if own > t:
                assert mine == own
                later += own < math.inf
            else:
                assert mine <= t
                before += 1
    assert later >= 100 and before >= 100


def test_cells_of_many_boxes_at_once_are_each_ones():
    rng = np.random.default_rng(2)
    lo = np.concatenate([rng.uniform(-40, 40, size=(200, 2)),
                         rng.integers(-6, 6, size=(50, 2)) * CELL])  # on cell borders too
    size = np.concatenate([rng.uniform(0, 15, size=(200, 2)),
                           rng.integers(0, 3, size=(50, 2)) * CELL])
    bounds = np.hstack([lo, lo + size])
    assert cells_of_all(bounds) == tuple(cells_of(b) for b in bounds)


def test_boxes_in_the_same_cells_share_one_tuple_of_cells():
    # hundreds of thousands of hulls and entries meet the same few blocks of cells: they
    # hold one tuple each, not a copy apiece
    a = cells_of((0.5, 0.5, 7.0, 7.0))
    assert a == ((0, 0), (0, 1), (1, 0), (1, 1))
    assert cells_of((1.0, 1.0, 8.0, 8.0)) is a
    assert cells_of_all(np.array([[2.0, 3.0, 9.0, 10.0]]))[0] is a


def test_a_swept_knows_its_extent_and_whether_its_intervals_come_in_order():
    # extent against numpy's reductions of the rows' arrays; in_order against each pair of
    # neighbours: motions' chunks (in order), shuffled ones, ties, one interval, none
    rng = np.random.default_rng(29)
    orders = 0
    for n in [0, 1, 1, 2, 3, 5, 8] * 20:
        t = np.cumsum(rng.choice([0.0, 0.5, rng.random()], size=n))
        ends = t + rng.choice([0.0, 0.5], size=n)
        if rng.integers(3) == 0:
            perm = rng.permutation(n)
            t, ends = t[perm], ends[perm]
        out = [(float(a), float(z), box(x, y, x + 1 + rng.random(), y + 1 + rng.random()))
               for a, z, x, y in zip(t, ends, rng.normal(0, 20, n), rng.normal(0, 20, n),
                                     strict=True)]
        sw = Swept.of(out)
        if n == 0:
            assert sw.extent == () and sw.in_order
            continue
        b = sw.bounds
        assert sw.extent == (sw.t[:, 0].min(), sw.t[:, 1].max(), *b[:, :2].min(axis=0),
                             *b[:, 2:].max(axis=0))
        want = all(p[0] <= q[0] and p[1] <= q[1] for p, q in zip(out, out[1:], strict=False))
        assert sw.in_order == want
        orders += not want
    assert orders > 5  # some out of order


def test_reserving_a_swept_files_it_as_its_intervals_one_by_one():
    # a Swept's known bounds and cells (motions' chunks and a held body, long and short,
    # shifted) against the table working them out from each hull: the same rows, boxes,
    # grid and long cells
    rng = np.random.default_rng(30)
    for _ in range(30):
        sws = [_random_swept(rng) for _ in range(3)]
        long = (float(rng.integers(0, 50)), float(rng.integers(60, 200)), sws[0].geoms[0])
        sws.append(Swept.of([long]))
        a, b = ReservationTable(), ReservationTable()
        for k, sw in enumerate(sws):
            d = float(rng.integers(-10, 100)) / 4
            a.reserve(f"o{k}", sw, offset=d)
            b.reserve(f"o{k}", list(sw), offset=d)
        assert a._store.rows == b._store.rows
        n = a._store.n
        assert np.array_equal(a._store.box[:n], b._store.box[:n])
        assert np.array_equal(a._store.t[:n], b._store.t[:n])
        assert a._grid.by_cell == b._grid.by_cell and a._grid.long_cells == b._grid.long_cells
        assert a._store.rows == [(*a._store.t[i], *shapely.bounds(a._store.geom[i]))
                                 for i in range(n)]


@pytest.mark.slow
@pytest.mark.parametrize("few", [True, False])
def test_blocked_departures_of_bodies_and_motions_are_those_a_brute_force_finds(few):
    # blocked (gathering its own candidates) against every entry and hull tested with
    # shapely and the definition's interval [t0 - z, t1 - a] (widened by eps) merged: a
    # standing body (one hull) and motions, Python's way and numpy's
    rng = np.random.default_rng(31)
    found = 0
    for _ in range(60):
        table = _random_table(rng, n=int(rng.choice([40, 200])), few=few)
        st = table._store
        ignore = "o2" if rng.integers(2) else None
        skip = st.ids.get(ignore, -1)
        moving = _random_swept(rng)
        if rng.integers(2):  # diamonds: boxes that meet, bodies that may not
            moving = Swept.of([(a, z, shapely.affinity.rotate(g, 45)) for a, z, g in moving])
        for sw in (moving, Swept.of([(0.0, 0.0, moving.geoms[0])])):
            since = float(rng.integers(0, 120)) / 2
            until = since + float(rng.choice([0, rng.integers(0, 10), rng.integers(100, 7200)]))
            lo, hi = [], []
            for (a, z), g in zip(sw.t, sw.geoms, strict=True):
                for i in range(st.n):
                    if (st.alive[i] and not st.in_slot[i] and st.owner[i] != skip
                            and shapely.intersects(g, st.geom[i])):
                        low, high = st.t[i, 0] - z - 1e-9, st.t[i, 1] - a + 1e-9
                        if high >= since and low <= until:
                            lo.append(float(low))
                            hi.append(float(high))
            want = candidates.merged(lo, hi)
            assert table.blocked(sw, since, until, ignore=ignore) == want
            # and among the entries gathered near it (as a search asks, from rest)
            cells = sorted({c for cs in sw.cells for c in cs})
            near = table.nearby(cells, since, until + sw.extent[1], ignore=ignore)
            assert table.blocked(sw, since, until, ignore=ignore, among=near) == want
            found += bool(want)
    assert found >= 30
