"""The command line calls only the library's facade: every import in ``lotsim/cli/`` (those
inside functions too) is of the standard library, :mod:`lotsim.api`, :mod:`lotsim.errors`
or another module of ``lotsim.cli``."""

import ast
import sys

from conftest import ROOT

ALLOWED = ("lotsim.api", "lotsim.errors", "lotsim.cli")


def _imports(source: str) -> list[str]:
    """The modules ``source`` imports, anywhere in it (``from lotsim import api`` is
    ``lotsim.api``)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module == "lotsim":
            found += [f"lotsim.{alias.name}" for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            found.append(node.module)
    return found


def _refused(name: str) -> bool:
    top = name.split(".")[0]
    return not (top in sys.stdlib_module_names or top == "__future__"
                or name.startswith(ALLOWED))


def test_the_cli_imports_only_the_api_the_errors_and_the_standard_library():
    files = sorted((ROOT / "lotsim" / "cli").glob("*.py"))
    assert len(files) > 5
    wrong = [(path.name, name) for path in files for name in _imports(path.read_text())
             if _refused(name)]
    assert wrong == []


def test_imports_inside_functions_and_of_other_layers_are_seen():
    source = ("import argparse\nfrom lotsim import api, bench\n\n\ndef f():\n"
              "    from lotsim.sim.limits import Watchdog\n")
    assert [n for n in _imports(source) if _refused(n)] == ["lotsim.bench", "lotsim.sim.limits"]
