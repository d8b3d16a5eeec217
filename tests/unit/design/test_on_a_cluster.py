"""A layout's candidates prepared on a Dask cluster (``lotsim layout --scheduler``): the
same layouts as prepared here, each candidate a task of the cluster's."""

from __future__ import annotations

import pytest

import lotsim
from lotsim.cli import main

PLOT = ("boundary: [[0, 0], [40, 0], [40, 24], [0, 24]]\n"
        "gates: [{id: in, at: [20, 0]}]\nbays: {angles_deg: [90]}\n"
        "demand: {count: 4}\n")


def _found(result):
    """What a layout found, but the time each candidate took."""
    return [(e.index, e.label, e.bays, e.problem, e.yaml, e.mean_time_to_park, e.throughput)
            for e in result.ranked]


@pytest.mark.slow
def test_a_layout_on_a_dask_cluster_is_the_one_laid_out_here(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    plot = tmp_path / "plot.yaml"
    plot.write_text(PLOT)
    # two at a time here and there (the search looks whether to stop after each batch)
    settings = lotsim.LayoutSettings(offsets=1, orientations=1, prepared=4, workers=2)
    here = lotsim.layout(str(plot), settings=settings)
    assert len(here.ranked) >= 2 and here.best.bays > 0
    with distributed.LocalCluster(n_workers=2, processes=False, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        with distributed.get_task_stream(client=client) as tasks:
            there = lotsim.layout(str(plot), settings=settings, client=client)
        ran = [t["key"] for t in tasks.data]
    assert _found(there) == _found(here)
    # every candidate prepared was a task of the cluster's, two at a time (its threads)
    assert len(ran) == len(there.ranked) and all("evaluate_job" in str(key) for key in ran), ran

    # the command: the same lot written, its table the same but for the time it took
    out_here, out_there = tmp_path / "here.yaml", tmp_path / "there.yaml"
    args = ["layout", str(plot), "-o", "", "--offsets", "1", "--orientations", "1",
            "--prepared", "4"]
    assert main([*args[:3], str(out_here), *args[4:], "--jobs", "2"]) == 0
    with distributed.LocalCluster(n_workers=2, processes=False, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        assert main([*args[:3], str(out_there), *args[4:], "--scheduler",
                     cluster.scheduler_address]) == 0
    assert out_there.read_text() == out_here.read_text()


def test_a_scheduler_nobody_answers_at_is_one_line_and_nothing_written(tmp_path, capsys):
    pytest.importorskip("distributed")
    plot = tmp_path / "plot.yaml"
    plot.write_text(PLOT)
    out = tmp_path / "lot.yaml"
    assert main(["layout", str(plot), "-o", str(out), "--scheduler", "tcp://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lotsim: --scheduler: ") and "cannot reach a Dask scheduler" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()
    with pytest.raises(SystemExit) as stopped:  # one place or the other, not both
        main(["layout", str(plot), "-o", str(out), "--jobs", "2", "--scheduler", "tcp://x:1"])
    assert stopped.value.code == 2
