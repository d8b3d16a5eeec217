"""lotsim.sim.settings: the run's tuning and the GA's penalty are checked like every other
setting, by name, with the value found."""

import pytest

import lotsim
from lotsim.errors import SettingsError
from lotsim.sim.settings import GASettings, RunSettings, RunTuning


@pytest.mark.parametrize(("field", "value", "words"), [
    ("probes", 0, "expected 1 to 1000, found 0"),
    ("probes", 2.5, "expected an integer"),
    ("probe_floor", 0, "expected 1 to"),
    ("probe_rate", -1.0, "expected 0 to"),
    ("probe_rate", float("nan"), "found nan"),
    ("congested_for", -0.5, "seconds, found -0.5"),
    ("heuristics_kept", -1, "expected 0 to"),
    ("skip_fruitless", "yes", "expected true or false"),
    ("flow_window", 0, "expected 1 to 86400 seconds, found 0"),
])
def test_a_tuning_value_out_of_range_is_refused_by_name(field, value, words):
    with pytest.raises(SettingsError, match=words) as err:
        RunTuning(**{field: value})
    assert err.value.name == field


def test_tuning_is_a_run_setting_normalised_and_checked_like_the_others():
    tuning = RunTuning(congested_for=10, probe_rate=4)
    assert isinstance(tuning.congested_for, float) and isinstance(tuning.probe_rate, float)
    assert RunSettings(tuning=tuning).tuning is tuning
    with pytest.raises(SettingsError, match="expected RunTuning"):
        RunSettings(tuning={"congested_for": 10})
    prepared = lotsim.prepare(lotsim.EXAMPLE)
    with pytest.raises(SettingsError, match="did you mean 'tuning'"):
        lotsim.run(prepared, tunning=tuning)


def test_the_ga_penalty_for_a_car_that_never_parks_is_checked():
    assert GASettings(unparked_penalty=0).unparked_penalty == 0.0
    with pytest.raises(SettingsError, match="unparked_penalty: expected 0 to 86400 seconds"):
        GASettings(unparked_penalty=-1)
