"""Bays by use: the ADA 2010 count table read row by row as the standard prints it (an
oracle written apart from lotsim's table), the least sizes of accessible bays and their
aisles in inches, and the rule of which vehicle types may park in which bays."""

from __future__ import annotations

import math
import re
from fractions import Fraction
from types import SimpleNamespace

import pytest

from lotsim.lot.uses import USES, ada_accessible, ada_van, refused_bays

# ADA 2010 Standards, Table 208.2, as printed: total parking spaces provided in the
# facility → minimum number of required accessible parking spaces
TABLE_208_2 = """
1 to 25 | 1
26 to 50 | 2
51 to 75 | 3
76 to 100 | 4
101 to 150 | 5
151 to 200 | 6
201 to 300 | 7
301 to 400 | 8
401 to 500 | 9
501 to 1000 | 2 percent of total
1001 and over | 20, plus 1 for each 100, or fraction thereof, over 1000
"""


def table_reading(total: int) -> int:
    """The row of :data:`TABLE_208_2` that holds ``total``, read as its words say."""
    for line in TABLE_208_2.strip().splitlines():
        spaces, need = (part.strip() for part in line.split("|"))
        low, high = re.fullmatch(r"(\d+) (?:to (\d+)|and over)", spaces).groups()
        if not (int(low) <= total <= (int(high) if high else math.inf)):
            continue
        if need.isdigit():
            return int(need)
        if need == "2 percent of total":  # a fraction of a space is a space
            share = Fraction(2, 100) * total
            return int(share) + (share.denominator != 1)
        base, over = 20, total - 1000  # 1 for each 100, or fraction thereof
        extra = 0
        while over > 0:
            extra, over = extra + 1, over - 100
        return base + extra
    raise AssertionError(f"no row holds {total}")


BOUNDARIES = [1, 25, 26, 50, 51, 75, 76, 100, 101, 150, 151, 200, 201, 300, 301, 400, 401, 500,
              501, 1000, 1001, 1100, 1101, 1200, 1201, 2000, 2001]


@pytest.mark.parametrize("total", BOUNDARIES)
def test_the_accessible_count_is_the_table_s_row_at_every_boundary(total):
    assert ada_accessible(total) == table_reading(total)


def test_the_accessible_count_is_the_table_s_row_for_every_total_to_1300():
    assert [ada_accessible(n) for n in range(1, 1301)] == [table_reading(n)
                                                           for n in range(1, 1301)]
    # the figures a reader checks by eye
    assert (table_reading(25), table_reading(26), table_reading(501), table_reading(1001),
            table_reading(1100), table_reading(1101)) == (1, 2, 11, 21, 21, 22)


def test_one_in_six_or_fraction_of_the_accessible_spaces_is_van_accessible():
    for n in range(0, 60):
        least = next(v for v in range(0, 60) if 6 * v >= n)  # one for every six or fraction
        assert ada_van(n) == least


def test_the_least_sizes_are_the_standard_s_inches():
    inch = 0.0254
    acc, van = USES["accessible"], USES["van_accessible"]
    assert acc.least_width == pytest.approx(96 * inch)
    assert acc.least_aisle(2.5) == pytest.approx(60 * inch)
    assert van.least_aisle(132 * inch) == pytest.approx(60 * inch)
    assert van.least_aisle(2.5) == pytest.approx(96 * inch)
    assert acc.size_problem(2.44, None) is None  # 96 in written to the centimetre
    assert "at least 2.44 m wide (96 in)" in acc.size_problem(2.40, None)
    assert "at least 2.44 m (96 in)" in van.size_problem(2.5, 1.6)
    assert van.size_problem(3.36, 1.53) is None
    assert USES["standard"].least_aisle(2.5) is None and USES["ev"].least_aisle(2.5) is None


def car(name, marks=(), length=4.5, width=1.8):
    return SimpleNamespace(name=name, length=length, width=width, marks=frozenset(marks))


def bay(sid, use, width=2.5, length=5.0):
    return SimpleNamespace(id=sid, use=use, width=width, length=length)


def test_who_may_park_where():
    bays = [bay("S", "standard"), bay("C", "compact", 2.3, 4.6), bay("A", "accessible"),
            bay("V", "van_accessible", 3.4), bay("E", "ev"), bay("M", "motorcycle", 1.2, 2.4)]
    types = [car("plain"), car("badge", ["accessible"]), car("ev", ["ev"]),
             car("big", length=4.9), car("bike", ["motorcycle"], 2.2, 0.8)]
    may = {name: sorted({b.id for b in bays} - set(refused))
           for name, refused in refused_bays(bays, types).items()}
    assert may == {"plain": ["C", "S"], "badge": ["A", "C", "S", "V"], "ev": ["C", "E", "S"],
                   "big": ["S"], "bike": ["C", "M", "S"]}
    why = refused_bays(bays, types)["big"]["C"]
    assert "compact" in why and "4.90" in why
