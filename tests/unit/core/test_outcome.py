"""The one result convention of every search (:mod:`lotsim.core.outcome`)."""

import pytest

from lotsim.core.outcome import Outcome, Status


def test_an_outcome_holds_a_value_exactly_when_found():
    assert Outcome.of([1, 2]).found and Outcome.of([1, 2]).value == [1, 2]
    for status in (Status.INFEASIBLE, Status.OUT_OF_BUDGET, Status.NO_PATH):
        out = Outcome.failed(status, "why")
        assert not out.found and out.value is None and out.reason == "why"
    with pytest.raises(ValueError):
        Outcome(Status.FOUND)
    with pytest.raises(ValueError):
        Outcome(Status.NO_PATH, value=3)
    with pytest.raises(ValueError):
        Outcome.failed(Status.FOUND, "found is not a failure")
