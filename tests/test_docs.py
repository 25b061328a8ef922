"""The API reference site: its guides' code runs, its cross-references are checked, CI builds it."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import re
import shlex
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests import doc_blocks
from tests.conftest import ROOT
from tests.doc_blocks import PAGES, output_matches


def _roles():
    spec = importlib.util.spec_from_file_location("griffe_sphinx_roles",
                                                  ROOT / "docs_ext" / "griffe_sphinx_roles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_output_matching_rules():
    """The guides' output rule: rounding, round-off, the cut at "…"; a changed number fails.

    Mutation caught: numbers compared as text (0.969 against 0.9692 fails).
    """
    assert output_matches("toppra 0.969 0.995", "toppra 0.9692 0.99500000031")
    assert not output_matches("toppra 0.969", "toppra 0.975")
    assert output_matches("error=4.16e-17, time=…", "error=2.2e-16, time=1.96 ms")
    assert not output_matches("solved", "failed")
    assert not output_matches("a\nb", "a")


def _page_commands() -> list[tuple[str, str, int | None]]:
    """(page, command, exit code stated) of every bash block and inline command, each once."""
    seen: dict[str, tuple[str, str, int | None]] = {}
    for page in PAGES:
        text = (ROOT / page).read_text()
        found = [c for b in doc_blocks.blocks(text) if b.lang == "bash"
                 for c in doc_blocks.commands(b.code)]
        found += [(c, None) for c in doc_blocks.inline_commands(text) if _is_command(c)]
        for command, code in found:
            seen.setdefault(command, (page, command, code))
    return list(seen.values())


def _is_command(text: str) -> bool:
    """An inline ``scara-opt ...`` that is a whole command (it parses), not a name."""
    from scara_opt.cli.app import UsageError, build_parser

    words = shlex.split(text.split("|")[0])
    try:
        build_parser().parse_args(words[1:])
    except (UsageError, SystemExit):
        if any(w.startswith("--") for w in words):  # options: meant to run, and broken
            return True
        return False
    return True


def _console_commands() -> list[tuple[str, str, str]]:
    """(page, command, shown output) of every ``console`` block."""
    return [(page, command, shown) for page in PAGES
            for b in doc_blocks.blocks((ROOT / page).read_text()) if b.lang == "console"
            for command, shown in doc_blocks.console(b.code)]


@pytest.mark.parametrize("page", PAGES)
def test_every_python_block_runs_and_prints_what_it_shows(page, tmp_path, monkeypatch):
    """Each page's Python blocks run in order, in a scratch folder holding examples/ and
    robots/, as printed; a block that prints is followed by a ``text`` block showing its
    output, which must match (:func:`output_matches`).

    Mutations caught: the getting-started IK target moved out of reach (prints
    ``unreachable``, the guide shows ``solved``); a guide block whose output is not shown;
    the README's dask block with its placeholder scheduler address (issue 38: not every
    block ran).
    """
    monkeypatch.chdir(doc_blocks.scratch(tmp_path))
    text = (ROOT / page).read_text()
    scope: dict = {}
    for k, block in enumerate(b for b in doc_blocks.blocks(text) if b.lang == "python"):
        printed = doc_blocks.run_python(block, scope, f"{page} python block {k + 1}")
        if printed.strip() or block.shown:
            assert block.shown, f"{page}:{block.line} prints but shows no output:\n{printed}"
            assert output_matches(block.shown, printed), (
                f"{page}:{block.line} shows:\n{block.shown}\nbut prints:\n{printed}\n"
                f"(python -m tests.doc_blocks {page} --write refreshes it)")


@pytest.mark.parametrize("page, command, code", _page_commands(),
                         ids=lambda v: v if isinstance(v, str) and " " in v else "")
def test_every_command_of_the_docs_runs(page, command, code, tmp_path):
    """Each command of a bash block or of the prose runs in a shell, in a scratch folder,
    and exits 0 (or the code it states); install, build and serve commands are named in
    doc_blocks.NOT_RUN with the reason.

    Mutation caught: docs/planning.md's plan command (issue 38: it exited 2, "the start is in
    collision: link2 and column 53.205 mm deep"); the README's ``path --html circle.html``
    (a flag now) -> exit 2; each fails.
    """
    if (why := doc_blocks.not_run(command)) is not None:
        pytest.skip(f"not run here: {why}")
    assert command.startswith("scara-opt "), (
        f"{page}: {command!r} is neither a scara-opt command nor in doc_blocks.NOT_RUN")
    run = doc_blocks.run_command(command, doc_blocks.scratch(tmp_path))
    assert run.returncode == (code or 0), f"{page}: {command}\n{run.stdout}\n{run.stderr}"


@pytest.mark.parametrize("page, command, shown", _console_commands(),
                         ids=lambda v: v if isinstance(v, str) and " " in v else "")
def test_every_console_command_prints_what_it_shows(page, command, shown, tmp_path):
    """Each ``$ command`` of a console block prints what the page shows after it (stdout
    then stderr, :func:`output_matches`).

    Mutation caught: a changed figure in docs/planning.md's ``scara-opt run`` output -> the
    line differs, fails.
    """
    run = doc_blocks.run_command(command, doc_blocks.scratch(tmp_path))
    printed = run.stdout + run.stderr
    assert output_matches(shown, printed), (
        f"{page}: $ {command}\nshows:\n{shown}\nprints:\n{printed}\n(python -m "
        f"tests.doc_blocks {page} --write refreshes it)")


@pytest.mark.parametrize("page", PAGES)
def test_every_toml_block_loads_as_what_it_is(page, tmp_path):
    """A page's TOML blocks load: a cell snippet as a cell, a robot snippet as a robot, a
    program snippet as a program (relative paths from examples/).

    Mutation caught: docs/planning.md's cell snippet with ``allowed = [["link4", "nest"]]``
    and no obstacle named nest (issue 38: copied as shown it raised UnknownBodyError when a
    checker was built) -> fails.
    """
    import scara_opt as so

    for block in doc_blocks.blocks((ROOT / page).read_text()):
        if block.lang != "toml":
            continue
        loaded = doc_blocks.load_toml_block(block.code, tmp_path)
        if isinstance(loaded, so.Cell):  # its allowed pairs name bodies that exist
            so.CollisionChecker(so.load_robot("zavar2024"), loaded)


def test_the_harness_fails_a_wrong_shown_output(tmp_path, monkeypatch):
    """A shown output that is wrong fails: a number off by more than its rounding, a line
    too many; ``--write`` replaces a wrong line and keeps a matching one with its cut.

    Mutation caught: output_matches ignoring the line count -> the extra line passes, fails.
    """
    assert not output_matches("1.906 [0.99480318]", "1.918 [0.99480318]")
    assert not output_matches("a\nb", "a\nb\nc")
    assert doc_blocks._merged("kept 1.90 …\nold 3\n", "kept 1.904 s\nold 4\n") == \
        "kept 1.90 …\nold 4\n"


def test_readme_quickstart_runs_without_a_flip(tmp_path, monkeypatch):
    """The README's quickstart runs as printed; its timed path has no jump (no elbow flip)
    and is not waved through with allow_jumps (issue: the demo flipped the elbow).

    Mutation: ``arc = circle`` in the README -> time_parameterize refuses the jump, fails.
    """
    monkeypatch.chdir(doc_blocks.scratch(tmp_path))
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    code = next(b for b in blocks if "time_parameterize" in b and "ik_path" in b)
    assert "allow_jumps" not in code
    scope: dict = {}
    with contextlib.redirect_stdout(io.StringIO()):
        exec(compile(code, "README quickstart", "exec"), scope)  # noqa: S102
    assert scope["path"].ok and scope["path"].jumps == ()
    assert max(r.max() for r in scope["traj"].check_limits().values()) <= 1.0


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
