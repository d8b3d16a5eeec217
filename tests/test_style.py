"""ruff is part of the test run, so the README's one test command also lints."""

import shutil
import subprocess
import sys

import pytest

from conftest import ROOT


def test_ruff_is_clean():
    ruff = shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is not installed (pip install -e '.[test]')")
    done = subprocess.run([ruff, "check", "lotsim", "tests", "benchmarks"], cwd=ROOT,
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stdout + done.stderr


def test_python_dash_m_lotsim_runs():
    done = subprocess.run([sys.executable, "-m", "lotsim", "cars"], cwd=ROOT,
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0
    assert "valet" in done.stdout and "vclass" in done.stdout


def test_a_virtual_environment_in_the_work_tree_is_not_tracked():
    git = shutil.which("git")
    if git is None or not (ROOT / ".git").exists():
        pytest.skip("not a git work tree (or no git): nothing to ignore")
    done = subprocess.run([git, "check-ignore", "-q", ".venv/bin/python"], cwd=ROOT,
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, ".venv/ is not in .gitignore"
