"""Every ```python block of the README and of docs/*.md runs as written.

The blocks of one page are one session (a later block uses what an earlier one made), run
from a fresh folder that holds the shipped scenarios, as a user would from the repository's
root. A block of prompts (``>>>``) is a doctest and its printed answers must match; any
other block must run without an error. A block tagged ```` ```python no-run ```` is shown,
not run here: a long example, such as a training loop, or the README's example of an
optional extra (``tests/unit/envs/`` runs that one). It must still compile.

A page whose code needs an optional extra (:data:`NEEDS`) skips without it, saying which,
unless ``LOTSIM_REQUIRE_EXPORTS=1`` (set by ``.ci/run``), where the missing module fails.
"""

from __future__ import annotations

import doctest
import importlib
import os
import re
from pathlib import Path

import pytest

from conftest import ROOT

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)
SHOWN = re.compile(r"^```python[ \t]+no-run[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)
NEEDS: dict[str, tuple[tuple[str, ...], str]] = {
    "export.md": (("scenariogeneration", "xmlschema", "ezdxf"),
                  "its examples read the ASAM XSDs of the openscenario extra and write DXF "
                  "(pip install 'lotsim[openscenario,dxf]')"),
    "import.md": (("ezdxf",), "its example writes and reads DXF (pip install 'lotsim[dxf]')"),
    "learning.md": (("gymnasium", "pettingzoo"),
                    "its examples step the learning environments of the learn extra (pip "
                    "install 'lotsim[learn]')"),
}
"""A page whose blocks need an optional extra: page name → (its modules, why it skips)."""


def blocks(page: Path) -> list[tuple[int, str]]:
    """The page's ```python blocks, each with the line it starts on."""
    text = page.read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start()) + 2, m.group(1)) for m in BLOCK.finditer(text)]


def shown_blocks(page: Path) -> list[tuple[int, str]]:
    """The page's ```python no-run blocks, each with the line it starts on."""
    text = page.read_text(encoding="utf-8")
    return [(text.count("\n", 0, m.start()) + 2, m.group(1)) for m in SHOWN.finditer(text)]


def test_the_pages_with_python_have_blocks_found():
    found = {p.name for p in PAGES if blocks(p)}
    assert {"README.md", "python.md", "layout.md", "export.md", "learning.md"} <= found
    assert [p.name for p in PAGES if shown_blocks(p)] == ["README.md", "bench.md", "learning.md"]
    text = "```python\nrun = 1\n```\n```python no-run\nshown = 2\n```\n"
    assert [m.group(1) for m in BLOCK.finditer(text)] == ["run = 1\n"]
    assert [m.group(1) for m in SHOWN.finditer(text)] == ["shown = 2\n"]


@pytest.mark.parametrize("page", [p for p in PAGES if shown_blocks(p)], ids=lambda p: p.name)
def test_the_blocks_shown_and_not_run_compile(page):
    for line, code in shown_blocks(page):
        compile(code, f"{page.name}:{line}", "exec")


def test_a_failing_block_is_reported(tmp_path, monkeypatch):
    page = tmp_path / "page.md"
    page.write_text("text\n```python\nimport lotsim\nlotsim.no_such_name\n```\n")
    monkeypatch.chdir(tmp_path)
    with pytest.raises(AssertionError, match=r"page.md:3.*no_such_name"):
        run_page(page, {})


def run_page(page: Path, namespace: dict) -> int:
    """Run the page's blocks in order in ``namespace``; the number run."""
    parser, runner = doctest.DocTestParser(), doctest.DocTestRunner(verbose=False)
    found = blocks(page)
    for line, code in found:
        where = f"{page.name}:{line}"
        if code.lstrip().startswith(">>>"):
            test = parser.get_doctest(code, namespace, where, str(page), line - 1)
            out: list[str] = []
            result = runner.run(test, out=out.append, clear_globs=False)
            namespace.update(test.globs)  # the doctest ran in a copy of the session
            assert result.failed == 0, f"{where}: a doctest failed\n{''.join(out)}"
        else:
            try:
                exec(compile(code, where, "exec"), namespace)
            except Exception as exc:
                raise AssertionError(f"{where}: {type(exc).__name__}: {exc}") from exc
    return len(found)


SLOW_PAGES = ("layout.md",)
"""Pages whose code lays out a plot (tens of seconds): run in the slow set."""


@pytest.mark.parametrize("page", [
    pytest.param(p, marks=pytest.mark.slow) if p.name in SLOW_PAGES else p
    for p in PAGES if blocks(p)], ids=lambda p: p.name)
def test_page_code_runs_as_written(page, tmp_path, monkeypatch):
    if page.name in NEEDS:
        modules, why = NEEDS[page.name]
        for module in modules:
            if os.environ.get("LOTSIM_REQUIRE_EXPORTS") == "1":
                importlib.import_module(module)
            else:
                pytest.importorskip(module, reason=why)
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios", target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    assert run_page(page, {"__name__": "__main__"}) == len(blocks(page))
