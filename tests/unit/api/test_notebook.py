"""In a notebook, a run, a prepared lot and a validation report show themselves: the
formatters IPython calls give HTML and PNG that hold what lotsim says elsewhere."""

from __future__ import annotations

import pytest

from conftest import ROOT

IPython = pytest.importorskip("IPython")


@pytest.fixture(scope="module")
def shell():
    from IPython.core.interactiveshell import InteractiveShell

    from lotsim.api.notebook import register

    ip = InteractiveShell.instance()
    assert register(ip)
    return ip


@pytest.fixture(scope="module")
def quickstart():
    import lotsim

    report = lotsim.validate(ROOT / "scenarios" / "quickstart.yaml")
    return report, lotsim.run(report.prepared)


def test_a_run_shows_its_counts_and_its_replay(shell, quickstart):
    _, result = quickstart
    shown, _ = shell.display_formatter.format(result)
    page = shown["text/html"]
    m = result.metrics()
    assert f"<td>served</td><td style='text-align:right'>{int(m['served'])}</td>" in page
    assert "<iframe srcdoc=" in page and "lotsim-replay" in page


def test_a_prepared_lot_shows_its_picture_and_a_report_its_table(shell, quickstart):
    report, _ = quickstart
    shown, _ = shell.display_formatter.format(report.prepared)
    assert shown["image/png"][:8] == b"\x89PNG\r\n\x1a\n"
    page = shell.display_formatter.format(report)[0]["text/html"]
    free = len(report.prepared.lot.free_slots)
    for name, ids in report.usable().items():
        assert f"<td>{name}</td><td style='text-align:right'>{len(ids)} of {free}</td>" in page
    assert "ok — " in page


def test_import_lotsim_registers_only_where_a_shell_runs(monkeypatch):
    from lotsim.api import notebook

    monkeypatch.setenv("LOTSIM_NO_NOTEBOOK", "1")
    assert not notebook.register_if_interactive()
    monkeypatch.delenv("LOTSIM_NO_NOTEBOOK")
    assert not notebook.register(object())  # not a shell


def test_long_work_shows_its_progress_in_the_cell():
    from lotsim.api.notebook import NotebookProgress, progress_for

    shown = []

    class Handle:
        def update(self, obj, raw=False):
            shown.append(obj)

    def display(obj, display_id):
        shown.append(obj)
        return Handle()

    bar = NotebookProgress("planning trips", display=display)
    assert shown == []  # nothing until there is news: a lot from the cache shows nothing
    bar(1, 5)
    for k in range(2, 6):
        bar._last = -1.0  # as if a tenth of a second went by
        bar(k, 5)
    # shown as text, not as a string's repr with its quotes ('planning trips …' stayed in
    # the cell); and gone when done
    assert [repr(s) for s in shown[:-1]] == [f"planning trips {k}/5, ~0 s left"
                                             for k in range(1, 5)]
    assert shown[-1] == {}
    assert progress_for("x") is None  # not in a notebook's kernel

