"""A property test of the command line: generated argument lists either work or exit 2 in one line.

Each example runs ``main(argv)`` in-process with stdout/stderr captured. Commands and
options come from the real parser (:func:`scara_opt.cli.build_parser`); values are mixed
from valid ones and bad ones (NaN, inf, huge numbers, empty strings, NUL bytes, odd
text, folders where files are expected and the reverse). Sizes stay small where they are
valid so that every example is fast; huge ones are refused before any allocation.
"""

from __future__ import annotations

import atexit
import contextlib
import io
import shutil
import tempfile
import uuid
import warnings
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from scara_opt.cli import build_parser, main

DATA = Path(__file__).parent / "data"
TMP = Path(tempfile.mkdtemp(prefix="scara_opt_cli_fuzz_"))
atexit.register(shutil.rmtree, TMP, ignore_errors=True)
A_FILE = TMP / "a_file.txt"
A_FILE.write_text("not a robot, not a folder\n")

# "1_0": int() and float() take digit underscores, so it is a valid count; kept small ("1_000"
# made one example `compare --seeds 1_000`, 1,000 seeds: 150 s, and hypothesis mutated it further)
ODD = ["", " ", "nan", "NaN", "inf", "-inf", "1e308", "1e309", "-1e309", "0", "-0", "-1",
       "1e-300", "99999999999999999999999", "0x10", "1_0", "abc", "a\0b", "\0", "--",
       "-", "é", "\u2028", "1,2", "all", "tangent", str(TMP), str(A_FILE)]
NUMBERS = ["0", "0.1", "0.3", "-0.07", "0.05", "280", "-70", "1", "30", "45", "-0.2"]
ROBOTS = ["zavar2024", "peng2025", "nguyen", "inverted5", "fang", str(DATA / "arm6.urdf")]


def _subcommands() -> dict[str, list[str]]:
    """Each subcommand's option strings, read from the parser."""
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return {name: [s for a in p._actions for s in a.option_strings if s not in ("-h", "--help")]
            for name, p in sub.choices.items()}


COMMANDS = _subcommands()
VALUES = {  # valid values kept small, so that an example that works is fast
    "-n": ["1", "2", "5", "12", "100", "500", "10**9", "1000000000", "99999999999999999999999"],
    "--methods": ["lm", "ipopt", "analytic", "pso,lm", "all", "bogus", "lm,,ipopt", ","],
    "--method": ["lm", "auto", "analytic", "ipopt", "pso", "bogus"],
    "--populations": ["20", "20,40", "2", "0", "-5", "a,b", "10**6", "99999999999999"],
    "--iterations": ["1", "2", "3", "0", "-1", "10**9", "99999999999999"],
    "--seeds": ["1", "2", "0", "99999999999999999999999"],
    "--time": ["toppra", "ruckig", "quintic", "nope"],
    "--workers": ["1", "0"],
    "--dask": ["notanaddress"],
    "--tol": ["1e-9", "1e-6", "0", "-1", "1e-300", "nan", "inf"],
    "--yaw": ["0", "30", "tangent", "nan", "north"],
    "--seed": ["0", "1", "-1", "7"],
}
COUNTS = {"--xyz": 3, "--target": 3, "--circle": 4, "--line": 6, "--q-start": 4}
FLAGS = {"--mm", "--deg", "--json", "--all", "--force", "--quick", "--no-footprint",
         "--allow-jumps"}
SLOW = {"reproduce"}  # a valid reproduce takes seconds: its paper is always a bad one


def mostly(good: st.SearchStrategy, bad: st.SearchStrategy) -> st.SearchStrategy:
    """``good`` four times in five, else ``bad``."""
    return st.integers(0, 4).flatmap(lambda k: bad if k == 0 else good)


@st.composite
def argv(draw: st.DrawFn) -> list[str]:
    odd = st.sampled_from(ODD)
    number = mostly(st.sampled_from(NUMBERS) | st.floats(-0.4, 0.4).map(repr), odd)
    command = draw(st.sampled_from([*COMMANDS, "nope"]))
    args = [command]
    robot = draw(mostly(st.sampled_from(ROBOTS), odd))
    if command in ("fk", "ik", "compare", "path", "workspace"):
        args.append(robot)
    if command == "fk":
        nq = {"nguyen": 5, "inverted5": 5}.get(robot, 6 if robot.endswith(".urdf") else 4)
        args += draw(mostly(st.lists(number, min_size=nq, max_size=nq),
                            st.lists(number, max_size=7)))
    if command == "reproduce":
        args.append(draw(st.sampled_from(["nobody", "", "a\0b", "ALL"])))
    options = COMMANDS.get(command, ["--out", "-n"])
    if command == "path":  # one of the two shapes, most of the time
        if robot in ROBOTS and draw(st.booleans()):
            args[1] = "zavar2024"  # the circle below is in its workspace
        options = [o for o in options if o not in ("--circle", "--line")]
        shape = draw(st.sampled_from(["--circle", "--circle", "--line", None]))
        if shape == "--circle":
            args += ["--circle", *draw(st.sampled_from(
                [["0.28", "0", "0.05", "-0.07"]] * 3 + [["0", "0", "0", "-0.07"],
                 ["0.28", "0", "nan", "-0.07"], ["0.28", "0", "1e308", "-0.07"]]))]
        elif shape == "--line":
            args += ["--line", *draw(st.lists(number, min_size=6, max_size=6))]
        if draw(st.booleans()):
            args += ["-n", draw(st.sampled_from(["2", "5", "8"]))]
    chosen = draw(st.lists(st.sampled_from(options), max_size=4, unique=True)) if options else []
    for option in chosen:
        if option == "--out":
            continue  # added below
        args.append(option)
        if option in FLAGS:
            continue
        if option in COUNTS:
            args += draw(st.lists(number, min_size=COUNTS[option], max_size=COUNTS[option]))
        else:
            args.append(draw(mostly(st.sampled_from(VALUES.get(option, NUMBERS)), odd)))
    if "--out" in options and draw(st.integers(0, 9)) > 0:
        fresh = str(TMP / uuid.uuid4().hex)
        args += ["--out", draw(st.sampled_from(
            [fresh] * 10 + ["", "a\0b", "/", str(A_FILE), "/proc/scara_opt/x"]))]
    if command in ("ik", "compare") and "--xyz" not in args and "--target" not in args:
        args += ["--xyz" if command == "ik" else "--target", "0.3", "0", "-0.07"]
    if command == "compare":  # small sweeps unless the example chose its own
        for option, value in (("--iterations", "2"), ("--populations", "20"),
                              ("--seeds", "1"), ("--methods", "lm,pso")):
            if option not in args:
                args += [option, value]
    return args


@settings(max_examples=400, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(argv())
def test_cli_never_crashes(args):
    """Every generated argument list returns 0, 1 (``ik`` that did not solve, its status
    printed, stderr empty), or 2 with exactly one line ``scara-opt: error: ...`` on stderr;
    never a traceback, never another code.

    Mutations: main()'s ``except (ScaraOptError, UsageError, OSError)`` narrowed to
    ``except ScaraOptError``: argparse's usage errors escaped and the test failed; and
    ``check_path_text``'s NUL check removed: ``--out 'a\\0b'`` ended in ValueError.
    """
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
            warnings.catch_warnings():
        warnings.simplefilter("ignore")  # library warnings are not the property under test
        code = main(args)
    lines = err.getvalue().strip().splitlines()
    if code == 2:
        assert len(lines) == 1 and lines[0].startswith("scara-opt: error: "), (args, lines)
    elif code == 1:  # ik that did not solve: its status is printed, nothing on stderr
        printed = out.getvalue()
        assert args[0] == "ik" and not lines, (args, lines)
        assert any(word in printed for word in ("unreachable", "failed", "max_iter",
                                                 "no closed-form solution")), (args, printed)
    else:
        assert code == 0, (args, code, lines)
