"""SearchSettings: the defaults the search always had, checked on construction."""

import pickle

import pytest

from lotsim.errors import SettingsError
from lotsim.traffic.settings import SearchSettings
from lotsim.vehicles.model import KMH


def test_the_defaults_are_the_searchs_tuning_as_numbers_of_the_right_kind():
    s = SearchSettings()
    assert (s.speed_step, s.express, s.chunk, s.sample) == (5 * KMH, 6.0, 0.5, 0.2)
    assert (s.weight, s.min_budget, s.passing, s.depart_after, s.horizon) == (
        1.25, 20000, 2.0, 1e-6, 3600.0)
    again = SearchSettings(weight=2, passing=0, horizon=60)
    assert type(again.weight) is float and again.passing == 0.0 and again.horizon == 60.0
    assert SearchSettings() == s and hash(SearchSettings()) == hash(s)  # a memo's key
    assert pickle.loads(pickle.dumps(again)) == again


@pytest.mark.parametrize("field, value, message", [
    ("weight", 0.5, "expected 1 to 10, found 0.5"),
    ("speed_step", 0, "expected 0.1 to 10 m/s, found 0"),
    ("chunk", 0, "expected a positive number up to 10 s, found 0"),
    ("sample", float("nan"), "expected a positive number up to 1 m, found nan"),
    ("min_budget", 2.5, "expected an integer, found 2.5"),
    ("passing", -1, "expected 0 to 60 s, found -1"),
    ("depart_after", 0, "expected a positive number up to 1 s, found 0"),
    ("horizon", float("inf"), "expected a positive number of seconds, found inf"),
    ("express", "6", "expected a number, found '6'"),
])
def test_a_value_out_of_range_is_refused_with_the_field_and_what_was_expected(
        field, value, message):
    with pytest.raises(SettingsError) as err:
        SearchSettings(**{field: value})
    assert str(err.value) == f"{field}: {message}"
