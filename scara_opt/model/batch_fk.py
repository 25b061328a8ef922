"""Forward kinematics of many configurations at once: the one vectorised route.

The casadi expression of :attr:`Robot.symbolic_fk` (tip pose; tip position alone; every
joint origin), compiled to C once per machine (:mod:`scara_opt.model.compiled`; casadi's
virtual machine where no compiler works), mapped over a batch and evaluated in place on
numpy arrays (:class:`~scara_opt.model.buffers.FunctionArrays`). Chosen by measurement
(``benchmarks/bench_fk.py``): on the bundled robots and a 7-joint arm, at batches of 1 to
60,000 configurations, it was never slower than the numpy chain walk it replaced and up to
9x faster at population sizes (60-100).

Batches are padded to a power of two (at least 8) up to ``CHUNK`` columns and cut into
chunks beyond, so a handful of mapped Functions serves every size. One set of buffers per
robot, output, size and thread (casadi buffers carry state).
"""

from __future__ import annotations

import hashlib
import threading
from pathlib import Path
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from scara_opt.model import symbolic
from scara_opt.model.buffers import FunctionArrays
from scara_opt.model.compiled import compiled, source_hash

if TYPE_CHECKING:
    from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

#: the largest mapped batch; bigger batches are evaluated chunk by chunk
CHUNK = 4096


def kinematic_key(robot: Robot) -> str:
    """A hash of everything the chain's FK depends on (joints, axes, placements, the tip)."""
    cached = robot.__dict__.get("_kinematic_key")
    if cached is None:
        h = hashlib.sha256()
        for j in robot.chain:
            h.update(repr((j.kind, j.index, j.mimic, j.scaling, j.offset)).encode())
            h.update(np.ascontiguousarray(j.axis, float).tobytes())
            h.update(np.ascontiguousarray(j.placement, float).tobytes())
        h.update(np.ascontiguousarray(robot.tip_placement, float).tobytes())
        cached = robot.__dict__["_kinematic_key"] = h.hexdigest()
    return cached


def _build(robot: Robot, output: str, name: str) -> ca.Function:
    q = ca.SX.sym("q", robot.nq)
    origins, p, R = symbolic.chain_walk(robot.chain, robot.tip_placement, q)
    if output == "pose":
        rows = ca.vertcat(p, ca.reshape(R.T, 9, 1))
    elif output == "position":
        rows = p
    else:  # every joint origin, then the tip
        rows = ca.vertcat(*origins, p)
    return ca.Function(name, [q], [ca.cse(ca.simplify(rows))], ["q"], ["rows"])


def function(robot: Robot, output: str) -> ca.Function:
    """The single-configuration Function of ``output`` ("pose", "position", "origins")."""
    cache: dict[str, ca.Function] = robot.__dict__.setdefault("_batch_fk", {})
    if output not in cache:
        key = kinematic_key(robot)
        name = f"scara_opt_fk_{output}_{key[:12]}"
        code = source_hash(symbolic.__file__, Path(__file__))
        cache[output] = compiled(name, f"{key} {output} {code}",
                                 lambda: _build(robot, output, name))
    return cache[output]


def _arrays(robot: Robot, f: ca.Function, size: int) -> FunctionArrays:
    """This thread's buffers of ``f`` mapped over ``size`` columns (made once per robot)."""
    cache: dict[tuple, FunctionArrays] = robot.__dict__.setdefault("_batch_fk_arrays", {})
    key = (f.name(), size, threading.get_ident())
    if key not in cache:
        cache[key] = FunctionArrays(f.map(size), size)
    return cache[key]


def fk_arrays(robot: Robot, output: str, n: int) -> FunctionArrays:
    """The buffers that evaluate batches of exactly ``n`` rows (this thread's).

    Write the rows into ``arg["q"]``, call, read ``res["rows"]`` (valid until the next
    call): :func:`evaluate` without its padding and copies, for a caller that evaluates
    the same size again and again (a population). Unpadded, 100 rows take ~8 µs instead
    of the ~10 µs of a map of 128; a new size costs ~40 µs once per robot and thread.
    """
    return _arrays(robot, function(robot, output), n)


def evaluate(robot: Robot, output: str, Q: Array) -> Array:
    """Rows (n, rows) of ``output`` for checked configurations ``Q`` (n, nq)."""
    return evaluate_function(robot, function(robot, output), Q)


def evaluate_function(robot: Robot, kernel: ca.Function, Q: Array) -> Array:
    """Rows (n, k) of a one-configuration Function ``kernel`` for checked ``Q`` (n, nq).

    ``kernel``: ``q (nq,) -> rows (k,)`` (those names), padded and chunked as the module
    docstring says. :func:`evaluate` runs it on the FK outputs' Functions; kernels that
    compute more than the FK with it (the workspace's footprint test,
    :meth:`scara_opt.footprint.Footprint.kernel`) call it directly. Buffers per robot,
    Function name, size and thread.
    """
    n = Q.shape[0]
    if 0 < n <= CHUNK:  # one chunk (every population): no loop, one copy out
        f = _arrays(robot, kernel, max(8, 1 << (n - 1).bit_length()))
        f.arg["q"][:n] = Q
        f()
        return f.res["rows"][:n].copy()
    out = np.empty((n, kernel.size1_out(0)))
    for start in range(0, n, CHUNK):
        part = Q[start:start + CHUNK]
        size = max(8, 1 << (len(part) - 1).bit_length()) if len(part) else 8
        f = _arrays(robot, kernel, size)
        f.arg["q"][:len(part)] = part
        f()
        out[start:start + len(part)] = f.res["rows"][:len(part)]
    return out


def poses(robot: Robot, Q: Array) -> tuple[Array, Array]:
    """Tip positions (n, 3) [m] and rotations (n, 3, 3) of checked ``Q`` (n, nq)."""
    rows = evaluate(robot, "pose", Q)
    return rows[:, :3], rows[:, 3:].reshape(-1, 3, 3)


def positions(robot: Robot, Q: Array) -> Array:
    """Tip positions (n, 3) [m] of checked ``Q`` (n, nq) (no rotations computed)."""
    return evaluate(robot, "position", Q)


def origins(robot: Robot, Q: Array) -> Array:
    """Every joint frame's origin, then the tip: (n, len(chain) + 1, 3) [m]."""
    return evaluate(robot, "origins", Q).reshape(Q.shape[0], len(robot.chain) + 1, 3)
