"""Every example runs as a script (smoke test, reduced budgets) and saves its figures."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

import pytest

from tests.conftest import ROOT

EXAMPLES = {
    "zavar2024_metaheuristics.py": ["--quick"],
    "zavar2024_circle.py": [],
    "peng2025_workspace.py": [],
    "fang_trajectories.py": [],
    "nguyen_cutting_path.py": ["--quick"],
    "inverted5_redundancy.py": [],
    "own_urdf.py": [],
    "panda.py": [],
    "pick_and_place_cell.py": [],
    "scara_cell_planning.py": [],
}


def _has_robot_data() -> bool:
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        distribution("example-robot-data")
    except PackageNotFoundError:
        return False
    return True


def test_every_example_is_listed():
    """Each script in examples/ is smoke-tested here and listed in examples/README.md."""
    scripts = {p.name for p in (ROOT / "examples").glob("*.py")}
    assert scripts == set(EXAMPLES)
    readme = (ROOT / "examples" / "README.md").read_text()
    assert all(f"`{name}" in readme for name in scripts)


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_example_runs(name):
    """The script exits 0, prints a table and writes at least one PNG it names."""
    if name == "panda.py" and not _has_robot_data():
        pytest.skip("needs example-robot-data: pip install 'scara-opt[robots]'")
    env = {**os.environ, "MPLBACKEND": "Agg"}
    out = subprocess.run([sys.executable, str(ROOT / "examples" / name), *EXAMPLES[name]],
                         capture_output=True, text=True, timeout=600, env=env, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-2000:]
    written = [line.split("wrote ", 1)[1].strip() for line in out.stdout.splitlines()
               if "wrote " in line]
    assert written and all(p.endswith(".png") and os.path.isfile(p) for p in written), out.stdout
    assert importlib.util.find_spec("scara_opt") is not None
