"""The API reference site: its guides' code runs, its cross-references are checked, CI builds it."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.conftest import ROOT

GUIDES = ["index.md", "getting-started.md", "own-robot.md", "ik-methods.md", "time-optimal.md",
          "motion.md", "planning.md", "native-code.md"]


def _roles():
    spec = importlib.util.spec_from_file_location("griffe_sphinx_roles",
                                                  ROOT / "docs_ext" / "griffe_sphinx_roles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _tokens(line: str) -> list[str]:
    """Numbers and single non-space characters of a printed line."""
    return re.findall(rf"{_NUMBER}|\S", line)


def _same_number(shown: str, got: str) -> bool:
    """``got`` is what ``shown`` prints as, within its printed rounding; round-off (at most
    1e-9 in magnitude) shows as any other round-off."""
    e, a = float(shown), float(got)
    if abs(e) <= 1e-9:
        return abs(a) <= 1e-9
    mantissa, _, exponent = shown.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    step = 10.0 ** (int(exponent or 0) - decimals)
    return abs(a - e) <= 0.5 * step * 1.001 + 1e-12 * abs(e)


def output_matches(shown: str, printed: str) -> bool:
    """Whether ``printed`` is the output a guide ``shown``: line by line, the same text, the
    same numbers to their printed rounding; ``…`` ends a line's comparison (a time)."""
    want, got = shown.strip().splitlines(), printed.strip().splitlines()
    if len(want) != len(got):
        return False
    for w, g in zip(want, got, strict=True):
        cut = "…" in w
        wt, gt = _tokens(w.split("…")[0]), _tokens(g)
        if (len(gt) < len(wt)) if cut else (len(gt) != len(wt)):
            return False
        for x, y in zip(wt, gt[: len(wt)], strict=True):
            numeric = re.fullmatch(_NUMBER, x) and re.fullmatch(_NUMBER, y)
            if not (_same_number(x, y) if numeric else x == y):
                return False
    return True


def test_output_matching_rules():
    """The guides' output rule: rounding, round-off, the cut at "…"; a changed number fails.

    Mutation caught: numbers compared as text (0.969 against 0.9692 fails).
    """
    assert output_matches("toppra 0.969 0.995", "toppra 0.9692 0.99500000031")
    assert not output_matches("toppra 0.969", "toppra 0.975")
    assert output_matches("error=4.16e-17, time=…", "error=2.2e-16, time=1.96 ms")
    assert not output_matches("solved", "failed")
    assert not output_matches("a\nb", "a")


@pytest.mark.parametrize("page", GUIDES)
def test_every_guide_code_block_runs_and_prints_what_it_shows(page, monkeypatch):
    """Each guide's Python blocks run in order, from the repository root, as printed; a
    block that prints is followed by a ``text`` block showing its output, which must match
    (:func:`output_matches`).

    Mutations caught: the getting-started IK target moved out of reach (prints
    ``unreachable``, the guide shows ``solved``); a guide block whose output is not shown.
    """
    monkeypatch.chdir(ROOT)
    text = (ROOT / "docs" / page).read_text()
    scope: dict = {}
    pattern = r"```python\n(.*?)```(?:\s*(?:It prints:)?\s*```text\n(.*?)```)?"
    for k, (code, shown) in enumerate(re.findall(pattern, text, re.S)):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"docs/{page} block {k + 1}", "exec"), scope)  # noqa: S102
        printed = out.getvalue()
        if printed.strip() or shown:
            assert shown, f"docs/{page} block {k + 1} prints but shows no output:\n{printed}"
            assert output_matches(shown, printed), (
                f"docs/{page} block {k + 1} shows:\n{shown}\nbut prints:\n{printed}")


def test_readme_quickstart_runs_without_a_flip(monkeypatch):
    """The README's quickstart runs as printed; its timed path has no jump (no elbow flip)
    and is not waved through with allow_jumps (issue: the demo flipped the elbow).

    Mutation: ``arc = circle`` in the README -> time_parameterize refuses the jump, fails.
    """
    monkeypatch.chdir(ROOT)
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    code = next(b for b in blocks if "time_parameterize" in b and "ik_path" in b)
    assert "allow_jumps" not in code
    scope: dict = {}
    exec(compile(code, "README quickstart", "exec"), scope)  # noqa: S102
    assert scope["path"].ok and scope["path"].jumps == ()
    assert max(r.max() for r in scope["traj"].check_limits().values()) <= 1.0


def test_readme_full_pose_block_runs(monkeypatch):
    """The README's full-pose snippet (fk_se3 -> Target -> solve_ik) solves."""
    monkeypatch.chdir(ROOT)
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    code = next(b for b in blocks if "fk_se3" in b)
    scope: dict = {"so": __import__("scara_opt")}
    exec(compile(code, "README full pose", "exec"), scope)  # noqa: S102
    assert scope["res"].success


def test_sphinx_roles_become_checked_cross_references():
    """An existing target becomes an optional autoref (link if documented); a missing one a
    plain reference, which mkdocs --strict reports; relative names resolve in their scope.

    Mutation caught: exists() returning True for every path (broken references pass).
    """
    roles = _roles()
    ok = roles.convert(":func:`~scara_opt.solve_ik` and :class:`scara_opt.Target`")
    assert ok == ('<autoref identifier="scara_opt.solve_ik" optional><code>solve_ik</code>'
                  '</autoref> and <autoref identifier="scara_opt.Target" optional>'
                  "<code>scara_opt.Target</code></autoref>")
    assert roles.convert(":func:`~scara_opt.solve_ikk`") == "[`solve_ikk`][scara_opt.solve_ikk]"
    scoped = roles.convert(":meth:`Robot.from_urdf`", "scara_opt.model.robot.Robot.fk")
    assert 'identifier="scara_opt.model.robot.Robot.from_urdf"' in scoped
    assert roles.convert(":meth:`fk` :math:`θ u`") == "`fk` \\(θ u\\)"
    assert roles.exists("scara_opt.model.robot.Robot.metadata")  # an attribute the class documents
    assert roles.convert("A:\n\n.. math::\n    x^2\n\nB") == "A:\n\n\\[\nx^2\n\\]\n\nB"


def test_strict_build_fails_on_a_broken_docstring_reference(tmp_path):
    """mkdocs build --strict with the project's extension: clean for a good reference, an
    error naming the target for a broken one."""
    pytest.importorskip("mkdocstrings_handlers.python")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "index.md").write_text("# API\n\n::: demo_mod\n")
    config = textwrap.dedent(f"""\
        site_name: demo
        theme: {{name: readthedocs}}
        plugins:
          - mkdocstrings:
              handlers:
                python:
                  paths: ["."]
                  options:
                    extensions: ["{ROOT / 'docs_ext' / 'griffe_sphinx_roles.py'}:SphinxRoles"]
        """)
    (tmp_path / "mkdocs.yml").write_text(config)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)])}
    results = {}
    for name in ("solve_ik", "solve_ikk"):
        (tmp_path / "demo_mod.py").write_text(
            f'"""Demo."""\n\n\ndef f():\n    """Calls :func:`~scara_opt.{name}`."""\n')
        results[name] = subprocess.run(
            [sys.executable, "-m", "mkdocs", "build", "--strict"], cwd=tmp_path,
            env=env, capture_output=True, text=True, timeout=300)
    assert results["solve_ik"].returncode == 0, results["solve_ik"].stderr
    assert results["solve_ikk"].returncode != 0
    assert "scara_opt.solve_ikk" in results["solve_ikk"].stderr


def test_ci_builds_the_site_with_warnings_as_errors():
    """.ci/run installs the docs extra after the tests and runs mkdocs build --strict."""
    ci = (ROOT / ".ci" / "run").read_text()
    assert ci.index("python -m pytest") < ci.index('pip install ".[docs]"') \
        < ci.index("mkdocs build --strict")
    readme = (ROOT / "README.md").read_text()
    assert "mkdocs build --strict" in readme and "pip install \".[docs]\"" in readme
    nav = (ROOT / "mkdocs.yml").read_text()
    for page in Path(ROOT / "docs").glob("*.md"):
        assert page.name in nav, page
