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
