"""Every code block and command of the README and docs/, run, and its shown output checked.

What a page holds, and what is done with it:

* a ``python`` block runs (the page's blocks in order, in one scope); when it prints, the
  ``text`` block after it (``It prints:``) must show that output (:func:`output_matches`);
* a ``console`` block holds ``$ command`` lines, each followed by the output it shows;
  each command runs in a shell and its output (stdout, then stderr) must match;
* a ``bash`` block holds commands (``#`` comments, ``\\`` continuations): each runs in a
  shell and must exit 0, or the code a ``# exits N`` comment states;
* a ``toml`` block is loaded as what it is: a cell file (``[[obstacles]]``), a robot file
  (``[[joints]]``), a program file (``[[moves]]``); any other is parsed as TOML;
* an inline ``scara-opt ...`` in the prose that is a whole command (it parses) runs too.

Commands run in a scratch folder holding ``examples``, ``robots`` and ``tests`` (links to
the repository's), never in the repository; ``scara-opt`` is the installed script of this
interpreter. Commands that install, build the site or serve it are not run here
(:data:`NOT_RUN`, each with the reason; ``.ci/run`` runs the README's two install
commands as written). An unknown command is an error: classify it there.

To see or refresh what the blocks print (after a change of wording):

    python -m tests.doc_blocks docs/planning.md            # shown and printed, block by block
    python -m tests.doc_blocks docs/planning.md --write    # rewrite the shown outputs

``--write`` keeps each shown line that already matches (its ``…`` cuts too) and replaces
the others; review the diff.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import subprocess
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the pages whose blocks run
PAGES = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))]

#: commands (by their start) that are not run here, and why
NOT_RUN = {
    "python3.11 -m venv": ".ci/run runs the README's install commands as written",
    "pip install": "installs the package: .ci/run does, in a fresh virtual environment",
    "mkdocs build": ".ci/run builds the site with --strict; test_docs builds a small one",
    "mkdocs serve": "a web server that runs until stopped",
}

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


def line_matches(w: str, g: str) -> bool:
    """One shown line against one printed line (see :func:`output_matches`)."""
    cut = "…" in w
    wt, gt = _tokens(w.split("…")[0]), _tokens(g)
    if (len(gt) < len(wt)) if cut else (len(gt) != len(wt)):
        return False
    for x, y in zip(wt, gt[: len(wt)], strict=True):
        numeric = re.fullmatch(_NUMBER, x) and re.fullmatch(_NUMBER, y)
        if not (_same_number(x, y) if numeric else x == y):
            return False
    return True


def output_matches(shown: str, printed: str) -> bool:
    """Whether ``printed`` is the output a page ``shown``: line by line, the same text, the
    same numbers to their printed rounding; ``…`` ends a line's comparison (a time)."""
    want, got = shown.strip().splitlines(), printed.strip().splitlines()
    return len(want) == len(got) and all(line_matches(w, g) for w, g in zip(want, got,
                                                                            strict=True))


@dataclass
class Block:
    """A fenced block of a page: its language, text, the output shown after it, its line."""

    lang: str
    code: str
    line: int
    shown: str | None = None
    shown_span: tuple[int, int] | None = field(default=None, repr=False)  # chars in the page
    span: tuple[int, int] = field(default=(0, 0), repr=False)  # the code's, in the page


_FENCE = re.compile(r"^```(\w*)\n(.*?)^```\n", re.S | re.M)
_SHOWN = re.compile(r"\s*(?:It prints:)?\s*```text\n(.*?)^```\n", re.S | re.M)


def blocks(text: str) -> list[Block]:
    """The fenced blocks of a page, a ``text`` block after a python one as its output."""
    out: list[Block] = []
    pos = 0
    while (m := _FENCE.search(text, pos)) is not None:
        pos = m.end()
        lang, code = m.group(1), m.group(2)
        block = Block(lang, code, text.count("\n", 0, m.start()) + 1,
                      span=(m.start(2), m.end(2)))
        if lang == "python":
            shown = _SHOWN.match(text, m.end())
            if shown is not None:
                block.shown = shown.group(1)
                block.shown_span = (shown.start(1), shown.end(1))
                pos = shown.end()
        out.append(block)
    return out


def commands(code: str) -> list[tuple[str, int | None]]:
    """The commands of a ``bash`` block: (command, exit code a ``# exits N`` states)."""
    out = []
    for line in code.replace("\\\n", " ").splitlines():
        if not shlex.split(line, comments=True):
            continue
        stated = re.search(r"#.*\bexits (\d+)", line)
        command = " ".join(re.sub(r"(^|\s)#.*$", "", line).split())
        out.append((command, int(stated.group(1)) if stated else None))
    return out


def console(code: str) -> list[tuple[str, str]]:
    """The ``$ command`` lines of a ``console`` block, each with the output shown after it."""
    out: list[tuple[str, str]] = []
    for line in code.replace("\\\n", " ").splitlines():
        if line.startswith("$ "):
            out.append((line[2:].strip(), ""))
        elif out:
            out[-1] = (out[-1][0], out[-1][1] + line + "\n")
    return out


def inline_commands(text: str) -> list[str]:
    """The inline ``scara-opt ...`` spans of the prose (outside fenced blocks)."""
    prose = _FENCE.sub("", text)
    return [m.group(1) for m in re.finditer(r"`(scara-opt [^`]*)`", prose)
            if "…" not in m.group(1) and not m.group(1).startswith("scara-opt:")]


def not_run(command: str) -> str | None:
    """Why ``command`` is not run here (:data:`NOT_RUN`), or None."""
    return next((why for start, why in NOT_RUN.items() if command.startswith(start)), None)


def scratch(folder: Path) -> Path:
    """``folder`` with links to the repository's ``examples``, ``robots`` and ``tests``
    (the data files a clone holds, as the docs' examples use them); returns it."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in ("examples", "robots", "tests"):
        link = folder / name
        if not link.exists():
            link.symlink_to(ROOT / name)
    return folder


#: a stderr line that depends on the machine's state, not on the command: the one-off note
#: of a first call that compiles native code (docs/native-code.md)
MACHINE_NOTE = re.compile(r"^scara-opt: note: compiling native code .*\n?", re.M)


def run_command(command: str, cwd: Path, timeout: float = 600) -> subprocess.CompletedProcess:
    """``command`` in bash in ``cwd``, this interpreter's scripts first on the PATH.

    The note of a first call that compiles (:data:`MACHINE_NOTE`) is taken out of stderr.
    """
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}"
           f"{os.environ.get('PATH', '')}", "COLUMNS": "100"}
    run = subprocess.run(["bash", "-c", command], cwd=cwd, capture_output=True, text=True,
                         env=env, timeout=timeout)
    run.stderr = MACHINE_NOTE.sub("", run.stderr)
    return run


def run_python(block: Block, scope: dict, name: str) -> str:
    """Run a python block in ``scope``; returns what it printed."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block.code, name, "exec"), scope)  # noqa: S102
    return out.getvalue()


def load_toml_block(code: str, folder: Path) -> object:
    """Load a TOML block as the file it is (cell, robot, program), from ``folder``.

    ``folder`` gets links to the files of examples/, so that a snippet's relative paths
    (a program's ``cell = "scara_cell.toml"``) resolve as they would beside them.
    """
    import scara_opt as so

    for item in (ROOT / "examples").iterdir():
        if not (folder / item.name).exists():
            (folder / item.name).symlink_to(item)
    path = folder / "block.toml"
    path.write_text(code)
    if re.search(r"^\[\[obstacles\]\]", code, re.M):
        return so.load_cell(path)
    if re.search(r"^\[\[joints\]\]", code, re.M):
        return so.load_robot(path)
    if re.search(r"^\[\[moves\]\]", code, re.M):
        return so.load_program(path)
    return tomllib.loads(code)


def _show(page: str, write: bool) -> None:
    """Print (or, with ``write``, rewrite) the outputs of ``page``'s blocks."""
    import tempfile

    path = ROOT / page
    text = path.read_text()
    folder = scratch(Path(tempfile.mkdtemp(prefix="doc_blocks_")))
    scope: dict = {}
    edits: list[tuple[tuple[int, int], str]] = []
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        for k, block in enumerate(blocks(text)):
            if block.lang == "python":
                printed = run_python(block, scope, f"{page} block {k + 1}")
                print(f"--- {page}:{block.line} python\nshown:\n{block.shown or ''}"
                      f"printed:\n{printed}")
                if write and block.shown_span is not None:
                    edits.append((block.shown_span, _merged(block.shown or "", printed)))
            elif block.lang == "console":
                new = ""
                for command, shown in console(block.code):
                    run = run_command(command, scratch(folder / f"c{k}_{len(new)}"))
                    print(f"--- {page}:{block.line} $ {command}\nshown:\n{shown}printed:\n"
                          f"{run.stdout}{run.stderr}(exit {run.returncode})")
                    new += f"$ {command}\n" + _merged(shown, run.stdout + run.stderr)
                if write:
                    edits.append((block.span, new))
    finally:
        os.chdir(cwd)
    if write and edits:
        for (a, b), new in sorted(edits, reverse=True):
            text = text[:a] + new + text[b:]
        path.write_text(text)
        print(f"wrote {page}")


def _merged(shown: str, printed: str) -> str:
    """The printed output, keeping each shown line that already matches it (with its cut)."""
    want, got = shown.strip("\n").splitlines(), printed.strip("\n").splitlines()
    if not got:
        return ""
    lines = []
    for i, g in enumerate(got):
        w = want[i] if i < len(want) else None
        lines.append(w if w is not None and line_matches(w, g) else g)
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--write"]
    for page in args or PAGES:
        _show(page, "--write" in sys.argv)
