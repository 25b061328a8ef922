"""The house: no import circles, no names shadowing each other, one-line results."""

from __future__ import annotations

import ast
import importlib
import inspect
from pathlib import Path

import numpy as np

import scara_opt as so

PACKAGE = Path(so.__file__).parent


def _imports(path: Path, modules: set[str]) -> set[str]:
    """Modules of the package that ``path`` imports at run time (TYPE_CHECKING blocks aside)."""
    tree = ast.parse(path.read_text())
    skip = {id(n) for node in ast.walk(tree) if isinstance(node, ast.If)
            and "TYPE_CHECKING" in ast.unparse(node.test) for n in ast.walk(node)}
    name = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    package = name.removesuffix(".__init__") if path.name == "__init__.py" else \
        name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            subs = {f"{base}.{a.name}" for a in node.names} & modules
            found.update(subs if len(subs) == len(node.names) else subs | {base})
    return found & modules


def test_no_import_circle_anywhere_in_the_package():
    """Walk every module's imports (function-level ones too): no module reaches itself.

    Mutation caught: a backend importing the timing registry again (the old
    registry <-> backends circle), or robot.py importing from ik -> a circle, fails.
    """
    paths = {".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts).removesuffix(
        ".__init__"): p for p in PACKAGE.rglob("*.py")}
    graph = {m: _imports(p, set(paths)) - {m} for m, p in paths.items()}
    state: dict[str, int] = {}

    def visit(m: str, trail: list[str]) -> None:
        state[m] = 1
        for n in sorted(graph[m]):
            assert state.get(n) != 1, "import circle: " + " -> ".join(trail + [m, n])
            if n not in state:
                visit(n, trail + [m])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [])


def test_public_submodules_are_attributes_and_do_not_shadow_functions():
    """so.plots, so.comparison, so.workspace_analysis, ... after a bare ``import scara_opt``;
    the compare and workspace functions are not their modules.

    Mutation caught: the function compare imported over a module named compare (c.COLUMNS
    then fails), or a lazy submodule missing from the package's list.
    """
    for name in ("plots", "comparison", "workspace_analysis", "paths", "trajectory", "model",
                 "reports", "metaheuristics", "ik"):
        assert getattr(so, name).__name__ == f"scara_opt.{name}"
    c = importlib.import_module("scara_opt.comparison")
    assert c.COLUMNS and callable(so.compare) and so.compare is c.compare
    w = importlib.import_module("scara_opt.workspace_analysis")
    assert inspect.isfunction(so.workspace) and so.workspace is w.workspace


def test_every_result_prints_in_one_or_two_lines():
    """IKResult, BatchResult, JointPath, Trajectory, Workspace, Target and Robot reprs are
    short, arrays summarised.

    Mutation caught: BatchResult's dataclass repr (every array dumped over many lines).
    """
    robot = so.load_robot("zavar2024")
    targets = so.paths.line([0.3, 0.0, -0.07], [0.3, 0.1, -0.07], 40)
    path = so.ik_path(robot, targets)
    objects = [so.solve_ik(robot, targets[0]), so.solve_many(robot, np.array(
        [t.position for t in targets])), path, so.time_parameterize(path, robot),
        so.workspace(robot, 2000), targets[0], robot]
    for obj in objects:
        text = repr(obj)
        assert text.count("\n") <= 1 and len(text) < 400, text
    assert "no jumps" in path.summary()


HEAVY = ("pinocchio", "casadi", "scipy", "pandas", "matplotlib", "toppra", "yourdfpy")


def _fresh(code: str) -> str:
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, check=True)
    return out.stdout.strip()


def test_import_is_light_and_every_public_name_resolves():
    """``import scara_opt`` loads none of the heavy libraries (the CLI starts fast, and a
    Ctrl-C while they load reaches the command's one-line handler); every name of
    ``__all__`` then resolves, to the object its module defines.

    Mutations caught: an eager ``from scara_opt.comparison import compare`` in the package's
    ``__init__`` (pandas and pinocchio loaded at import); a name of ``__all__`` mapped to the
    wrong module (AttributeError).
    """
    loaded = _fresh(f"import sys, scara_opt; print([m for m in {HEAVY!r} if m in sys.modules])")
    assert loaded == "[]"
    for name in so.__all__:
        assert getattr(so, name) is not None
    assert so.solve_ik is importlib.import_module("scara_opt.ik").solve_ik


def test_metaheuristics_registered_without_the_package_import():
    """A program that imports only ``scara_opt.ik`` still finds every built-in method: the
    registry loads the modules of its BUILTIN_MODULES table at the first lookup.

    Mutation caught: ``BUILTIN_MODULES = ()`` ('pso' unknown in a fresh process).
    """
    names = _fresh("from scara_opt.ik import solvers; print(' '.join(solvers()))").split()
    assert {"pso", "gwo", "ca", "fa", "aco", "ga", "gha", "sfla", "lm", "ipopt"} <= set(names)
