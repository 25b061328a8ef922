"""casadi Functions evaluated in place on numpy arrays (no conversion per call)."""

from __future__ import annotations

import casadi as ca
import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


class FunctionArrays:
    """Numpy arrays wired to a (mapped) casadi Function's inputs and outputs, by name.

    Each array is ``(n, size)`` in C order: the memory of casadi's column-major
    ``(size, n)``. Calling the object evaluates in place. casadi buffers carry state:
    use one instance per thread (e.g. :func:`scara_opt.ik.lm_functions.phase_arrays`).

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
            # stubs, not code: casadi's .pyi requires `size`, which its SWIG wrapper fills
            # from the memoryview (its docstring: set_arg(0, memoryview(a))); numpy's stubs
            # give ndarray the buffer protocol (__buffer__) only for Python >= 3.12
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
