"""The shared argument checks: numbers, flags, robots, and the memory estimate with its override."""

from __future__ import annotations

import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt import checks
from scara_opt.model.robot import check_robot


def test_human_bytes_and_counts_read_well():
    """Binary units up to EiB, powers of ten beyond; counts with separators, then 1e+30.

    Mutation: human_bytes divides by 1000 instead of 1024 -> fails.
    """
    assert checks.human_bytes(512) == "512 B"
    assert checks.human_bytes(4 * 2**30) == "4 GiB"
    assert checks.human_bytes(32e12) == "29.1 TiB"
    assert checks.human_bytes(5.2e32) == "5.2e+32 B"
    assert checks.count_text(60_000) == "60,000"
    assert checks.count_text(10**30) == "1e+30"


def test_check_memory_refuses_above_the_limit_and_the_override_lifts_it(monkeypatch):
    """The estimate and the override are named; raising MAX_BYTES lets the call through.

    Mutation: check_memory compares with a fixed 4 GiB instead of MAX_BYTES -> fails.
    """
    with pytest.raises(so.InputError, match=r"about 4 GiB .*more than the 1 GiB allowed; "
                                            r"lower n, .*scara_opt.checks.MAX_BYTES"):
        monkeypatch.setattr(checks, "MAX_BYTES", 2**30)
        checks.check_memory("f(n=2**22)", 2**22, 1024, "lower n")
    monkeypatch.setattr(checks, "MAX_BYTES", 8 * 2**30)
    assert checks.check_memory("f(n=2**22)", 2**22, 1024, "lower n") == 4 * 2**30
    monkeypatch.setattr(checks, "MAX_BYTES", 100)
    with pytest.raises(so.InputError, match="200 B"):
        checks.check_memory("f", 2, 100, "lower n")


def test_memory_guard_turns_a_memory_error_into_advice():
    """A MemoryError inside the guarded block is an InputError naming the estimate.

    Mutation: memory_guard re-raises the MemoryError -> fails.
    """
    with pytest.raises(so.InputError, match=r"ran out of memory \(estimated 2 GiB\); lower n"):
        with checks.memory_guard("workspace(n=...)", 2 * 2**30, "lower n"):
            raise MemoryError


@pytest.mark.parametrize("value", [["1", "2"], "0.5", [True, False], {"a": 1}, [1, None],
                                   object(), [[1, 2], [3]]])
def test_float_array_refuses_strings_bools_and_non_numbers(value):
    """np.asarray(..., dtype=float) would parse "0.5" and count True as 1: both refused.

    Mutation: float_array accepts string and bool dtypes (kind "U", "b") -> fails.
    """
    with pytest.raises(so.InputError, match="numeric"):
        checks.float_array(value, "x")


def test_float_array_accepts_numbers_of_every_kind():
    """Python ints (even beyond int64), floats, numpy arrays of ints and floats."""
    np.testing.assert_array_equal(checks.float_array([1, 2.5], "x"), [1.0, 2.5])
    assert checks.float_array([10**30], "x")[0] == 1e30
    assert checks.float_array(np.arange(3), "x").dtype == np.float64


@pytest.mark.parametrize("value, match", [(True, r"True \(bool\)"), ("1", r"'1' \(str\)"),
                                          (10**400, "a finite number"), (math.nan, "finite"),
                                          (-1.0, ">= 0")])
def test_check_real_names_what_it_got(value, match):
    """Bools, strings, NaN and ints beyond the float range are refused by name, not raised.

    Mutation: check_real without the OverflowError branch (float(10**400) escapes) -> fails.
    """
    with pytest.raises(so.InputError, match=match):
        checks.check_real("tol", value, 0.0)


def test_check_robot_tells_to_load_a_name_first():
    """A robot name is answered with the call that loads it; anything else is named too.

    Mutation: check_robot without the str branch -> fails (generic message).
    """
    with pytest.raises(so.InputError, match=r"so.load_robot\('zavar2024'\)"):
        check_robot("zavar2024")
    with pytest.raises(so.InputError, match=r"None \(NoneType\)"):
        check_robot(None)


HUGE = [10**400, -10**400, 10**5000]  # beyond any float; 10**5000 beyond Python's int repr


def _huge_calls(robot):
    """Every entry point that takes a count, a budget or a length, fed one huge integer."""
    t = so.Target((0.3, 0.1, -0.07))
    calls = {"tol": lambda v: so.solve_ik(robot, t, tol=v),
             "solve_many tol": lambda v: so.solve_many(robot, [(0.3, 0.1, -0.07)], tol=v),
             "solve_many targets": lambda v: so.solve_many(robot, [(v, 0.1, -0.07)]),
             "ik_all tol": lambda v: so.ik_all(robot, t, tol=v),
             "workspace n": lambda v: so.workspace(robot, n=v),
             "workspace grid": lambda v: so.workspace(robot, n=1000, grid=v),
             "compare iterations": lambda v: so.compare(robot, [t], methods="pso", iterations=v,
                                                        progress=False),
             "compare populations": lambda v: so.compare(robot, [t], methods="pso",
                                                         populations=[v], progress=False),
             "Target": lambda v: so.Target((v, 0.0, 0.0)),
             "fk": lambda v: robot.fk([v, 0, 0, 0]),
             "circle n": lambda v: so.paths.circle((0.3, 0.0), 0.05, -0.07, n=v)}
    for method in so.solvers():
        for option in so.get_solver(method).defaults:
            calls[f"{method} {option}"] = \
                lambda v, m=method, o=option: so.solve_ik(robot, t, method=m, **{o: v})
    return calls


@pytest.mark.parametrize("value", HUGE, ids=["1e400", "-1e400", "1e5000"])
def test_huge_integers_anywhere_are_input_errors(robots, value):
    """10**400 (no float holds it) as tol, population, max_iter, any option of any method,
    workspace(n=), a grid, a coordinate...: a ScaraOptError naming it, never a bare
    OverflowError (``math.isnan(10**400)``, ``float(n)``) or ValueError (``repr`` of an int
    above 4,300 digits).

    Mutation caught: ``math.isnan(value)`` for ints again in ``check_number`` -> an
    OverflowError; ``count_text`` through ``float(n)`` again -> OverflowError; fails.
    """
    escaped = {}
    for name, call in _huge_calls(robots["zavar2024"]).items():
        try:
            call(value)
        except so.ScaraOptError as exc:
            assert len(str(exc)) < 600, name  # the number is not printed in full
        except Exception as exc:  # noqa: BLE001 (what the test looks for)
            escaped[name] = f"{type(exc).__name__}: {str(exc)[:80]}"
    assert not escaped


def test_a_huge_tol_or_budget_says_what_to_pass(robots):
    """The messages read ``tol=1e+400 is above 1``, ``population=1e+400 x ...``, and name the
    bound or the memory, with the number in short."""
    zavar = robots["zavar2024"]
    t = so.Target((0.3, 0.1, -0.07))
    with pytest.raises(so.InputError, match=r"tol=1e\+400 is above 1 \[m, rad\]"):
        so.solve_ik(zavar, t, tol=10**400)
    with pytest.raises(so.InputError, match=r"population=1e\+400 x iterations=200 .* memory"):
        so.solve_ik(zavar, t, method="pso", population=10**400)
    with pytest.raises(so.InputError, match=r"option max_iter=1e\+400 must be an integer in"):
        so.solve_ik(zavar, t, method="lm", max_iter=10**400)
    with pytest.raises(so.InputError, match=r"workspace\(n=1e\+400\) would need about"):
        so.workspace(zavar, n=10**400)


def test_count_text_and_short_repr_at_any_size():
    """Counts of any size in three digits and a power of ten; a repr Python refuses, named.

    Mutation caught: the exponent not lowered for 10**20 - 1 -> ``0.999e+20``; fails.
    """
    assert checks.count_text(10**20 - 1) == "9.99e+19"
    assert checks.count_text(-10**400) == "-1e+400"
    assert checks.count_text(10**5000) == "1e+5000"
    assert checks.short_repr(10**5000) == "1e+5000"
    assert checks.short_repr([10**5000]) == "a list holding an integer too long to print"
    assert checks.human_bytes(10**400) == "1e+400 B"
