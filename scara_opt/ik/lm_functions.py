"""The fast solver's Functions compiled once per machine, and each thread's arrays for them.

The iterations of :mod:`scara_opt.ik.lm_steps`, merged (common subexpressions) and
compiled to C once per machine (:mod:`scara_opt.model.compiled`; casadi's virtual machine
where no compiler works), cached per robot, task kind and batch size; the numpy arrays
they are evaluated in (:class:`~scara_opt.model.buffers.FunctionArrays`), one set per
thread; and the joint box the iterations take as an input.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path

import casadi as ca
import numpy as np

from scara_opt.ik import lm_steps, problem
from scara_opt.ik.base import default_q0
from scara_opt.ik.lm_steps import BUILDERS
from scara_opt.model import symbolic, tool_angle
from scara_opt.model.batch_fk import kinematic_key
from scara_opt.model.buffers import FunctionArrays
from scara_opt.model.compiled import compiled, source_hash
from scara_opt.model.robot import Array, Robot

#: the sources the iterations are built from (the builders, the task residual, the
#: symbolic FK, the yaw basis, the merge below): part of the compiled cache's key, so a
#: change to any of them compiles anew
SOURCES = (lm_steps.__file__, problem.__file__, symbolic.__file__, tool_angle.__file__,
           str(Path(__file__)))
_CODE = source_hash(*SOURCES)


def _merged(f: ca.Function, name: str) -> ca.Function:
    """``f`` renamed ``name`` with its common subexpressions merged (fewer instructions)."""
    outputs = f.call(f.sx_in())
    if hasattr(ca, "cse"):  # casadi >= 3.6: ~10-30 % fewer instructions
        outputs = ca.cse(outputs)
    return ca.Function(name, f.sx_in(), outputs, f.name_in(), f.name_out())


def step_function(robot: Robot, phase: str, kind: str, jit: bool = True) -> ca.Function:
    """The ``phase`` ("lm" or "slide") Function of one target, built or loaded once.

    With ``jit`` it is the C compiled once per machine and kept in the cache folder
    (:mod:`scara_opt.model.compiled`: loaded in well under a millisecond in later processes;
    where no C compiler works, casadi's virtual machine runs it). Without, the virtual
    machine always. The cache key holds the robot's kinematics, the task kind and the
    source of the modules that build it, so a change to any compiles anew.
    """
    cache: dict[tuple, ca.Function] = robot.__dict__.setdefault("_ik_lm_cache", {})
    if (phase, kind, jit) not in cache:
        key = kinematic_key(robot)
        name = f"scara_opt_{phase}_{kind}_{key[:12]}"

        def build() -> ca.Function:
            return _merged(BUILDERS[phase](robot, kind), name)

        cache[(phase, kind, jit)] = compiled(name, f"{key} {phase} {kind} {_CODE}", build) \
            if jit else build()
    return cache[(phase, kind, jit)]


def cached_step(robot: Robot, phase: str, kind: str, n: int = 1,
                jit: bool = True) -> ca.Function:
    """:func:`step_function` mapped over ``n`` columns (one per target), built once."""
    cache: dict[tuple, ca.Function] = robot.__dict__.setdefault("_ik_lm_maps", {})
    if (phase, kind, n, jit) not in cache:
        f = step_function(robot, phase, kind, jit)
        cache[(phase, kind, n, jit)] = f if n == 1 else f.map(n)
    return cache[(phase, kind, n, jit)]


@dataclass
class PhaseArrays:
    """The iterations' :class:`FunctionArrays` for ``n`` targets, sharing ``par``, ``box``.

    Attributes:
        lm, slide: the arrays of :func:`build_lm_step` and :func:`build_slide_step`.
        par: (n, n_par) the NLP parameters of each target; box: (n, 3 nq) the limits.
        newton: the arrays of :func:`build_newton_step`.
    """

    lm: FunctionArrays
    slide: FunctionArrays
    par: Array
    box: Array
    newton: FunctionArrays


def phase_arrays(robot: Robot, kind: str, n: int = 1, jit: bool = True) -> PhaseArrays:
    """This thread's :class:`PhaseArrays` for ``robot``, task kind and ``n`` columns."""
    cache: dict[tuple, PhaseArrays] = robot.__dict__.setdefault("_ik_lm_arrays", {})
    key = (kind, n, jit, threading.get_ident())
    if key not in cache:
        lm = FunctionArrays(cached_step(robot, "lm", kind, n, jit), n)
        shared = {"par": lm.arg["par"], "box": lm.arg["box"]}
        slide = FunctionArrays(cached_step(robot, "slide", kind, n, jit), n, shared)
        newton = FunctionArrays(cached_step(robot, "newton", kind, n, jit), n, shared)
        cache[key] = PhaseArrays(lm, slide, shared["par"], shared["box"], newton)
    return cache[key]


def limits(robot: Robot) -> tuple[Array, Array]:
    """``box`` (3 nq,) = [lower, upper, ranges] and the default ``q0``, cached per limits."""
    lo, hi = robot.lower, robot.upper
    cache: dict[bytes, tuple[Array, Array]] = robot.__dict__.setdefault("_ik_lm_limits", {})
    key = lo.tobytes() + hi.tobytes()
    if key not in cache:
        span = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
        cache[key] = np.concatenate([lo, hi, span]), default_q0(robot)
    return cache[key]

