"""The package's layers depend one way: every import in ``lotsim/`` (function-level ones and
those only for type checkers included) goes from a layer to itself or to one on its left,

    errors <- core <- {lot, vehicles} <- roadmap <- maneuvers <- traffic <- scenario <- sim
           <- io <- render <- bench <- design <- envs <- api <- cli

and the independent checker (``lotsim.verify``) imports nothing of lotsim but
``lotsim.errors``. A ``_private`` name is not imported from another package. Gymnasium and
PettingZoo (the ``learn`` extra) are imported by ``lotsim.envs`` alone, so that ``import
lotsim`` works without them."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "lotsim"

ORDER = ["errors", "core", ("lot", "vehicles"), "roadmap", "maneuvers", "traffic", "scenario",
         "sim", "io", "render", "bench", "design", "envs", "api", "cli"]
RANK = {name: i for i, layer in enumerate(ORDER)
        for name in (layer if isinstance(layer, tuple) else (layer,))}
RANK["verify"] = RANK["core"]  # anyone may check a result; it imports only errors


def layer_of(module: str) -> str:
    """``lotsim.roadmap.graph`` -> ``roadmap``; the package root and ``__main__`` are the top."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] != "__main__" else "cli"


def module_of(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """Every ``lotsim`` import of a file: (line, module, names imported from it)."""
    return imports_in(path.read_text(), module_of(path), is_package=path.name == "__init__.py")


def imports_in(source: str, module: str, *, is_package: bool = False
               ) -> list[tuple[int, str, list[str]]]:
    """Every ``lotsim`` import of ``source``, the text of ``module``."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, []) for a in node.names
                    if a.name.split(".")[0] == "lotsim"]
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against this module's package
                base = module.split(".")[: len(module.split(".")) - node.level + is_package]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "lotsim":
                continue
            base = PACKAGE.parent.joinpath(*target.split("."))
            for a in node.names:  # ``from lotsim import bench`` imports the module lotsim.bench
                is_module = (base / a.name).is_dir() or base.joinpath(f"{a.name}.py").is_file()
                out.append((node.lineno, f"{target}.{a.name}", []) if is_module
                           else (node.lineno, target, [a.name]))
    return out


def edges() -> list[tuple[str, int, str, list[str]]]:
    return [(module_of(p), line, target, names)
            for p in sorted(PACKAGE.rglob("*.py")) if p.name != "__init__.py" or p.parent != PACKAGE
            for line, target, names in imports(p)]


def against_layers(found: list[tuple[str, int, str, list[str]]]) -> list[str]:
    """The imports of ``found`` (module, line, target, names) that go against the layers."""
    wrong = []
    for module, line, target, names in found:
        src, dst = layer_of(module), layer_of(target)
        if target == "lotsim" and set(names) <= {"__version__"}:
            ok = True  # the package's version, which every layer may write into its files
        elif src == "verify":
            ok = dst in ("verify", "errors")
        elif src in ("lot", "vehicles") and dst in ("lot", "vehicles"):
            ok = src == dst or dst == "vehicles"  # a lot may know vehicle sizes; not back
        else:
            ok = RANK[dst] <= RANK[src]
        if not ok:
            wrong.append(f"{module}:{line} imports {target} ({src} -> {dst})")
    return wrong


def test_every_import_goes_down_the_layers():
    wrong = against_layers(edges())
    assert not wrong, "imports against the layers:\n" + "\n".join(wrong)


def test_no_private_name_is_imported_from_another_package():
    def package(module: str) -> str:
        return ".".join(module.split(".")[:2])

    wrong = [f"{module}:{line} imports {name} from {target}"
             for module, line, target, names in edges()
             for name in names
             if name.startswith("_") and not name.startswith("__")
             and package(module) != package(target)]
    assert not wrong, "\n".join(wrong)


def test_the_rule_reads_a_wrong_import():
    # the reader sees function-level and type-checking imports, and the rule catches them
    src = ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from lotsim.sim import x\n"
           "def f():\n    from lotsim.cli import main\n")
    tree = [n for n in ast.walk(ast.parse(src)) if isinstance(n, ast.ImportFrom)]
    targets = [n.module for n in tree if n.module.startswith("lotsim")]
    assert targets == ["lotsim.sim", "lotsim.cli"]
    assert RANK[layer_of("lotsim.cli")] > RANK[layer_of("lotsim.roadmap.graph")]
    assert layer_of("lotsim") == "cli" and layer_of("lotsim.verify.checker") == "verify"
    # the reader and the rule themselves, on a roadmap module importing upwards twice
    found = [("lotsim.roadmap.x", line, target, names)
             for line, target, names in imports_in(src, "lotsim.roadmap.x")]
    assert [target for _, _, target, _ in found] == ["lotsim.sim", "lotsim.cli"]
    assert against_layers(found) == ["lotsim.roadmap.x:3 imports lotsim.sim (roadmap -> sim)",
                                     "lotsim.roadmap.x:5 imports lotsim.cli (roadmap -> cli)"]
    assert against_layers([("lotsim.sim.x", 1, "lotsim.roadmap.model", [])]) == []


LEARN = ("gymnasium", "pettingzoo")


def outside_imports(source: str) -> set[str]:
    """The top-level names of the modules ``source`` imports (absolute imports)."""
    out = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            out.add(node.module.split(".")[0])
    return out


def test_only_the_learning_environments_import_gymnasium_and_pettingzoo():
    wrong = [f"{module_of(p)} imports {name}" for p in sorted(PACKAGE.rglob("*.py"))
             if module_of(p).split(".")[:2] != ["lotsim", "envs"]
             for name in sorted(outside_imports(p.read_text()) & set(LEARN))]
    assert not wrong, "\n".join(wrong)
    assert outside_imports("import gymnasium.spaces\nfrom pettingzoo import ParallelEnv\n"
                           "from . import x\n") == set(LEARN)
    envs = set().union(*(outside_imports(p.read_text())
                         for p in (PACKAGE / "envs").glob("*.py")))
    assert set(LEARN) <= envs


def test_lotsim_imports_without_the_learn_extra_and_its_environments_say_what_is_missing():
    # gymnasium and pettingzoo made unimportable in a fresh interpreter
    blocker = ("import sys\n"
               "class Block:\n"
               "    def find_spec(self, name, path=None, target=None):\n"
               f"        if name.split('.')[0] in {LEARN!r}:\n"
               "            raise ImportError(f'No module named {name!r}')\n"
               "sys.meta_path.insert(0, Block())\n"
               "import lotsim, lotsim.api, lotsim.cli\n"
               "print(lotsim.Live.__name__, lotsim.run.__name__)\n"
               "try:\n"
               "    import lotsim.envs\n"
               "except ImportError as err:\n"
               "    print(type(err).__name__, err)\n")
    done = subprocess.run([sys.executable, "-c", blocker], capture_output=True, text=True,
                          cwd=PACKAGE.parent, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "Live run", "LearnUnavailable lotsim.envs needs gymnasium and pettingzoo: pip install "
                    "'lotsim[learn]'"]
