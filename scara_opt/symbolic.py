"""Symbolic forward kinematics in casadi, built by walking the Pinocchio model tree.

The PyPI ``pin`` wheel has no ``pinocchio.casadi``, so the expression is assembled
here from the joint placements, joint kinds and axes, and the tip placement that
:class:`scara_opt.Robot` reads from its Pinocchio model.

Mapped over a batch and evaluated through :meth:`casadi.Function.buffer`
(:class:`FunctionArrays`), the same expression is also the fast route for small batches
(:func:`small_batch_poses`): ~1 µs per call plus ~0.2 µs per configuration, where the
numpy chain walk of :meth:`Robot.fk_batch` pays ~80 µs per call.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from scara_opt.robot import ChainJoint, Robot

Array = NDArray[np.float64]

#: batches up to this many configurations go through casadi (:func:`small_batch_poses`):
#: poses, and positions only (half the instructions); measured crossovers with the numpy
#: walk of :meth:`Robot.fk_batch` (``benchmarks/bench_fk.py``): ~150 and ~600
SMALL_BATCH, SMALL_BATCH_POSITIONS = 128, 512


def _rotation(axis: np.ndarray, angle: ca.SX) -> ca.SX:
    """3×3 rotation about a constant unit ``axis`` by a symbolic ``angle`` (Rodrigues)."""
    c, s = ca.cos(angle), ca.sin(angle)
    K = ca.SX(np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]]))
    return ca.SX.eye(3) + s * K + (1 - c) * (K @ K)


def build_symbolic_fk(chain: Sequence[ChainJoint], tip_placement: np.ndarray,
                      name: str = "fk") -> ca.Function:
    """casadi Function ``q (nq,) -> (p (3,), R (3×3))`` of the tip pose in the world frame.

    A mimic joint of the chain turns by ``scaling * q[index] + offset``; every other joint
    by ``q[index]`` (continuous joints included: ``q`` holds their angle).

    Args:
        chain: the movable joints in order (placement in the parent frame, kind, axis,
            the entry of ``q`` that drives it).
        tip_placement: 4×4 placement of the tip in the last joint's frame [m].
        name: the Function's name.
    """
    q = ca.SX.sym("q", sum(not j.mimic for j in chain))
    R: ca.SX = ca.SX.eye(3)
    p: ca.SX = ca.SX.zeros(3)
    for j in chain:
        p = p + R @ ca.DM(j.placement[:3, 3])
        if not np.array_equal(j.placement[:3, :3], np.eye(3)):
            R = R @ ca.DM(j.placement[:3, :3])
        value = j.scaling * q[j.index] + j.offset if j.mimic else q[j.index]
        if j.kind == "prismatic":
            p = p + (R @ ca.DM(j.axis)) * value
        else:
            R = R @ _rotation(j.axis, value)
    p = p + R @ ca.DM(tip_placement[:3, 3])
    R = R @ ca.DM(tip_placement[:3, :3])
    return ca.Function(name, [q], [ca.simplify(p), ca.simplify(R)], ["q"], ["p", "R"])


class FunctionArrays:
    """Numpy arrays wired to a (mapped) casadi Function's inputs and outputs, by name.

    Each array is ``(n, size)`` in C order: the memory of casadi's column-major
    ``(size, n)``. Calling the object evaluates in place. casadi buffers carry state:
    use one instance per thread (:func:`phase_arrays`).

    Attributes:
        arg: input arrays by input name; res: output arrays by output name.
    """

    def __init__(self, f: ca.Function, n: int, shared: dict[str, Array] | None = None) -> None:
        shared = shared or {}
        self.arg = {name: shared.get(name, np.zeros((n, f.size1_in(i))))
                    for i, name in enumerate(f.name_in())}
        self.res = {name: np.zeros((n, f.size1_out(i)))
                    for i, name in enumerate(f.name_out())}
        if hasattr(f, "buffer"):  # casadi >= 3.6: no argument conversion per call
            self._buffer, self._eval = f.buffer()
            for i, a in enumerate(self.arg.values()):
                self._buffer.set_arg(i, memoryview(a.reshape(-1)))  # type: ignore[call-arg,arg-type]
            for i, a in enumerate(self.res.values()):
                self._buffer.set_res(i, memoryview(a.reshape(-1)))  # type: ignore[call-arg,arg-type]
        else:  # pragma: no cover - older casadi
            def evaluate() -> None:
                out = f.call([a.T for a in self.arg.values()])
                for a, v in zip(self.res.values(), out, strict=True):
                    a[...] = np.asarray(v).T.reshape(a.shape)

            self._eval = evaluate

    def __call__(self) -> None:
        """Evaluate every column; results land in :attr:`res`."""
        self._eval()


def _padded(n: int) -> int:
    """The mapped size used for ``n`` configurations: a power of two, at least 8."""
    return max(8, 1 << (n - 1).bit_length())


def small_batch_poses(robot: Robot, Q: Array, rotations: bool = True) -> tuple[Array, Array | None]:
    """Tip positions (n, 3) [m] and rotations (n, 3, 3) of ``Q`` (n, nq), n >= 1.

    :attr:`Robot.symbolic_fk` mapped over a power-of-two batch (unused columns are zero)
    and evaluated in place, one instance per robot, output, size and thread (casadi
    buffers carry state). ``Q`` must already be checked (finite, (n, nq)). With
    ``rotations=False`` only the positions are computed (half the instructions) and the
    rotations are ``None``.
    """
    n = Q.shape[0]
    size = _padded(n)
    cache: dict[tuple, FunctionArrays] = robot.__dict__.setdefault("_small_batch_fk", {})
    key = (size, rotations, threading.get_ident())
    if key not in cache:
        q = ca.SX.sym("q", robot.nq)
        p, R = robot.symbolic_fk(q)
        rows = ca.cse(ca.vertcat(p, ca.reshape(R.T, 9, 1))) if rotations else p
        f = ca.Function("pose_rows", [q], [rows], ["q"], ["pose"])  # p, then R row by row
        cache[key] = FunctionArrays(f.map(size), size)
    f = cache[key]
    f.arg["q"][:n] = Q
    f()
    out = f.res["pose"][:n]
    if not rotations:
        return out.copy(), None
    return out[:, :3].copy(), out[:, 3:].reshape(n, 3, 3).copy()
