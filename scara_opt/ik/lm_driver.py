"""The fast solver's start loop in C (``lm_driver.c``), on the compiled iterations.

:class:`scara_opt.ik.lm_run.Run` calls the compiled casadi iterations a few times a start;
its Python work between the calls costs about as much as the iterations on a 6- or
7-joint arm. :class:`Driver` runs the same loop in C: ``lm_driver.c`` calls the
Functions' C entry points (in the libraries :mod:`scara_opt.model.compiled` keeps) on the
same arrays, with the same constants, and gives the same iterates, counts and history,
bit for bit. Where a Function is not compiled (no C compiler, ``jit=False``) there is no
driver and ``Run`` runs. :func:`phase_driver` makes this thread's driver of a robot and task
kind.
"""

from __future__ import annotations

import ctypes
import math
import threading
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from scara_opt.ik.lm_functions import phase_arrays, step_function
from scara_opt.ik.lm_run import SLIDE_TOL, STALL_CALLS, STALL_DECREASE, STEP_TOL
from scara_opt.ik.lm_steps import EVALS, ITERATIONS, LAMBDA0, LAMBDA_MAX
from scara_opt.model.buffers import FunctionArrays
from scara_opt.model.compiled import c_function, library_path
from scara_opt.model.robot import Array, Robot

_P = ctypes.c_void_p
_I = ctypes.c_int64
_D = ctypes.c_double
#: the largest nq the C loop's buffers hold
MAX_NQ = 64


class _Phase(ctypes.Structure):
    """``struct lm_phase`` of lm_driver.c."""

    _fields_ = [("f", _P), ("arg", _P), ("res", _P), ("iw", _P), ("w", _P),
                ("q", _P), ("lam", _P), ("q_next", _P), ("lam_next", _P),
                ("e_next", _P), ("step", _P), ("extra", _P),
                ("iterations", _I), ("evaluations", _I)]


class _RunState(ctypes.Structure):
    """``struct lm_run`` of lm_driver.c."""

    _fields_ = [("lm", _Phase), ("newton", _Phase), ("slide", _Phase),
                ("nq", _I), ("stall_calls", _I),
                ("lambda0", _D), ("lambda_max", _D), ("step_tol", _D), ("slide_tol", _D),
                ("stall_decrease", _D), ("e_tol", _D), ("nearest", _I),
                ("budget", _I), ("iterations", _I), ("evaluations", _I), ("slide_needed", _I),
                ("best", _D), ("history", _P), ("n_history", _I), ("history_size", _I)]


def _address(a: np.ndarray) -> int:
    return int(a.ctypes.data)


def _entry(f: ca.Function) -> tuple[int, ctypes.CDLL] | None:
    """The C entry point of a compiled Function (and its library, kept loaded), or None."""
    path = library_path(f.name())
    if path is None:
        return None
    lib = ctypes.CDLL(str(path))
    size = getattr(lib, f"{f.name()}_casadi_int_size", None)
    if size is None or size() != ctypes.sizeof(ctypes.c_longlong):
        return None
    return ctypes.cast(getattr(lib, f.name()), _P).value or 0, lib


class Driver:
    """One thread's C start loop for one robot and task kind (see the module docstring).

    The interface of :class:`~scara_opt.ik.lm_run.Run` that ``lm_search`` uses:
    :meth:`reset` (a new solve), ``budget``, :meth:`start`, and the counts ``iterations``,
    ``evaluations``, ``history``.
    """

    def __init__(self, phases: dict[str, tuple[ca.Function, FunctionArrays, int]],
                 counts: dict[str, tuple[int, int]], constants: dict[str, float], nq: int,
                 start: Any, libraries: list[ctypes.CDLL]) -> None:
        self._keep: list[Any] = [libraries]  # what the C side points into stays alive
        self._c = _RunState(nq=nq, **constants)
        for name, phase in phases.items():
            setattr(self._c, name, self._phase(*phase, counts[name]))
        self._start = start
        self._q, self._e = np.zeros(nq), np.zeros(1)
        self._args = (ctypes.addressof(self._c), _address(self._q), _address(self._e))
        self._history = np.zeros(0)
        self.history: list[float] = []

    def _phase(self, f: ca.Function, arrays: FunctionArrays, entry: int,
               counts: tuple[int, int]) -> _Phase:
        """``struct lm_phase`` of ``f`` (C entry point ``entry``) on ``arrays``."""
        arg = (_P * f.sz_arg())(*[_address(a) for a in arrays.arg.values()])
        res = (_P * f.sz_res())(*[_address(a) for a in arrays.res.values()])
        iw, w = np.zeros(max(f.sz_iw(), 1), np.int64), np.zeros(max(f.sz_w(), 1))
        self._keep += [arg, res, iw, w]
        named = {**arrays.arg, **arrays.res}

        def at(*names: str) -> int:  # the first of the names f has (0: none)
            return next((_address(named[n]) for n in names if n in named), 0)

        return _Phase(entry, ctypes.addressof(arg), ctypes.addressof(res), _address(iw),
                      _address(w), at("q"), at("lam"), at("q_next"), at("lam_next"),
                      at("e_next"), at("step"), at("slide", "pull"), *counts)

    def reset(self, e_tol: float, max_iter: int, nearest: bool = True) -> Driver:
        """Start a solve: counts zero, best ∞, the history empty (room for ``max_iter``).

        ``nearest``: the slide toward ``q0`` and the polish after phase 1 (lm's option).
        """
        c = self._c
        c.nearest = int(nearest)
        c.e_tol, c.iterations, c.evaluations, c.slide_needed, c.best = e_tol, 0, 0, 1, math.inf
        size = 2 * max_iter + 8  # a start's calls: each counts >= 1 but a slide's retry
        if len(self._history) < size:
            self._history = np.zeros(size)
        c.history, c.history_size = _address(self._history), len(self._history)
        self.history = []
        return self

    @property
    def budget(self) -> int:
        """Iterations left to the current start."""
        return int(self._c.budget)

    @budget.setter
    def budget(self, value: int) -> None:
        self._c.budget = value

    @property
    def iterations(self) -> int:
        """Iterations over the starts so far."""
        return int(self._c.iterations)

    @property
    def evaluations(self) -> int:
        """FK evaluations over the starts so far."""
        return int(self._c.evaluations)

    def start(self, q: Array) -> tuple[Array, float]:
        """All three phases from one start: (q, ‖r‖²), as ``Run.start``."""
        self._q[:] = q
        self._c.n_history = 0
        status = self._start(*self._args)
        if status != 0:  # a Function's error (-1) or a full history (-2): a bug
            raise RuntimeError(f"lm_driver.c: lm_start failed ({status})")
        self.history += self._history[:self._c.n_history].tolist()
        return self._q.copy(), float(self._e[0])


def make(phases: dict[str, tuple[ca.Function, FunctionArrays]],
         counts: dict[str, tuple[int, int]], constants: dict[str, float],
         nq: int) -> Driver | None:
    """A :class:`Driver` on compiled phases, or ``None`` where it cannot run.

    ``None`` where a phase is not compiled, the C loop does not compile, or ``nq`` exceeds
    :data:`MAX_NQ`.

    Args:
        phases: "lm", "newton", "slide": the Function and its one-column arrays.
        counts: per phase, the iterations and FK evaluations one call counts.
        constants: the loop's constants, by the field names of ``struct lm_run``.
        nq: joints.
    """
    start = c_function(Path(__file__).with_name("lm_driver.c"), "lm_start", [_P, _P, _P],
                       ctypes.c_int)
    if nq > MAX_NQ or start is None:
        return None
    entries: dict[str, tuple[ca.Function, FunctionArrays, int]] = {}
    libraries = []
    for name, (f, arrays) in phases.items():
        if (entry := _entry(f)) is None:
            return None
        entries[name] = (f, arrays, entry[0])
        libraries.append(entry[1])
    return Driver(entries, counts, constants, nq, start, libraries)


def phase_driver(robot: Robot, kind: str, jit: bool = True) -> Driver | None:
    """This thread's C start loop on the one-target :func:`phase_arrays`, or ``None``.

    ``None`` where the phases are not compiled (``jit=False``, no C compiler):
    :class:`~scara_opt.ik.lm_run.Run`, the same loop in Python, runs.
    """
    cache: dict[tuple, Driver | None] = robot.__dict__.setdefault("_ik_lm_driver", {})
    key = (kind, jit, threading.get_ident())
    if key not in cache:
        cache[key] = _make_driver(robot, kind) if jit else None
    return cache[key]


def _make_driver(robot: Robot, kind: str) -> Driver | None:
    """:func:`make` on this thread's compiled phases and the loop's constants."""
    f = phase_arrays(robot, kind, 1, True)
    phases = {phase: (step_function(robot, phase, kind, True), getattr(f, phase))
              for phase in ("lm", "newton", "slide")}
    counts = {phase: (ITERATIONS[phase], EVALS[phase]) for phase in phases}
    constants = {"stall_calls": STALL_CALLS, "lambda0": LAMBDA0, "lambda_max": LAMBDA_MAX,
                 "step_tol": STEP_TOL, "slide_tol": SLIDE_TOL, "stall_decrease": STALL_DECREASE}
    return make(phases, counts, constants, robot.nq)
