"""``scara-opt doctor``: what this installation runs on, and what is compiled or falls back.

:func:`report` gives the lines the command prints: the versions of Python and the
libraries, the platform, the C compiler (or why there is none), the cache folder (where,
writable or not, its libraries and whether each passes its check), then what each piece of
native code did in this process after a short run on a bundled robot that uses all of them
(loaded from the cache, built now, or falling back, and why).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from importlib import metadata
from pathlib import Path

from scara_opt.model import compiled

#: the distributions whose versions the report lists (name as installed)
PACKAGES = ("scara-opt", "numpy", "scipy", "casadi", "pin", "coal", "ompl", "yourdfpy",
            "toppra", "ruckig", "pandas", "matplotlib", "meshcat", "distributed")

#: the bundled robot the report runs on (it has a circular base footprint)
ROBOT = "peng2025"

#: what each native library does, by the start of its name
ROLES = (("scara_opt_fk_", "batch forward kinematics"),
         ("scara_opt_lm_", "fast IK: Levenberg-Marquardt iteration"),
         ("scara_opt_slide_", "fast IK: slide toward q0"),
         ("scara_opt_newton_", "fast IK: Newton step"),
         ("scara_opt_footprint_", "workspace: base exclusion zone test"),
         ("lm_driver", "fast IK: start loop (C)"),
         ("fa_sweep", "FA: all-pairs sweep (C)"),
         ("ga_breed", "GA: crossover and mutation (C)"),
         ("aco_ants", "ACO: ant sampling (C)"),
         ("toppra_passes", "toppra: the two reachability passes (C)"),
         ("scara_opt_bodies_", "collision: robot body placements"),
         ("edge_kernel", "collision: edge proofs (C++, coal)"))


def versions() -> list[str]:
    """``name version`` of Python and each of :data:`PACKAGES` (``not installed`` if absent)."""
    out = [f"python {sys.version.split()[0]}"]
    for name in PACKAGES:
        try:
            out.append(f"{name} {metadata.version(name)}")
        except metadata.PackageNotFoundError:
            out.append(f"{name} not installed")
    return out


def _where() -> str:
    """Which variable chose the cache folder."""
    if os.environ.get(compiled.CACHE_ENV):
        return f"${compiled.CACHE_ENV}"
    return "$XDG_CACHE_HOME/scara_opt" if os.environ.get("XDG_CACHE_HOME") else \
        "the default, ~/.cache/scara_opt"


def _writable(folder: Path) -> str:
    """``"writable"``, or why not (tried by writing a file: a permission check lies for root)."""
    if not folder.exists():
        return "not created yet"
    try:
        with tempfile.TemporaryFile(dir=folder):
            return "writable"
    except OSError as exc:
        return f"NOT writable ({exc.strerror})"


def cache_lines() -> list[str]:
    """The cache folder: where, whether writable, its libraries and those failing the check."""
    folder = compiled.cache_dir()
    lines = [f"cache folder: {folder} (from {_where()}; {_writable(folder)})"]
    libraries = sorted(folder.glob("*.so")) if folder.is_dir() else []
    size = sum(p.stat().st_size for p in libraries)
    damaged = [p.name for p in libraries if not compiled.check_library(p)]
    lines.append(f"  {len(libraries)} libraries, {size / 1024:.0f} KiB; "
                 f"{len(damaged)} fail their size and SHA-256 check"
                 + (f" (built again when next used): {', '.join(damaged)}" if damaged else ""))
    return lines


def compiler_lines() -> list[str]:
    """The C compiler, its origin and version; or why there is none."""
    chain = compiled.toolchain()
    if os.environ.get(compiled.NO_COMPILE_ENV) == "1":
        off = [f"  {compiled.NO_COMPILE_ENV}=1: nothing is compiled"]
    else:
        off = []
    if isinstance(chain, compiled.Toolchain):
        return [f"C compiler: {' '.join(chain.command)} (from {chain.origin}): {chain.version}",
                f"  flags: {' '.join(compiled.FLAGS)}", *off]
    return [f"C compiler: none ({chain})", *off]


def exercise(robot_name: str = ROBOT) -> None:
    """Use every piece of native code once on a bundled robot (building what is missing)."""
    import numpy as np

    import scara_opt as so
    from scara_opt.metaheuristics import aco, fa, ga_breed
    from scara_opt.trajectory import toppra_passes

    robot = so.load_robot(robot_name)
    rng = np.random.default_rng(0)
    Q = robot.lower + rng.random((8, robot.nq)) * (robot.upper - robot.lower)
    P = robot.fk_batch(Q)[:, :3, 3]
    so.solve_ik(robot, P[0])
    so.solve_many(robot, P)
    for kernel in (fa._kernel, ga_breed._kernel, aco._kernel, toppra_passes._kernel):
        kernel()
    so.workspace(robot, n=1000, seed=0)  # the footprint's test compiled with the FK
    checker = so.CollisionChecker(robot, so.Cell([so.Sphere("ball", 0.05, xyz=(0.3, 0, 0))]))
    checker.distances_many(Q)  # the edge proofs' kernel and the bodies' placements


def _role(name: str) -> str:
    return next((role for start, role in ROLES if name.startswith(start)), "")


def native_lines() -> list[str]:
    """One line per native library this process used: its state and role."""
    lines, why = [], ""
    for native in compiled.natives():
        state = {"loaded": "compiled (loaded from the cache)", "built": "compiled (built now)",
                 "fallback": "FALLS BACK", "off": "off"}[native.state]
        role = _role(native.name)
        detail = f"; {native.detail}" if native.detail and native.state != "fallback" else ""
        lines.append(f"  {native.name:<38} {role:<40} {state}{detail}")
        if native.state == "fallback" and native.detail != why:  # each reason once
            why = native.detail
            lines.append(f"      why: {why}")
    return lines


def report(robot_name: str = ROBOT) -> list[str]:
    """The lines ``scara-opt doctor`` prints (runs :func:`exercise` first)."""
    head = ["versions: " + ", ".join(versions()),
            f"platform: {compiled.platform_id()}", *compiler_lines()]
    exercise(robot_name)
    natives = compiled.natives()
    falls = sum(n.state == "fallback" for n in natives)
    return [*head, *cache_lines(),
            f"native code, after a short run on {robot_name} ({len(natives) - falls} of "
            f"{len(natives)} compiled, {falls} falling back):", *native_lines()]


def cmd_doctor(args: argparse.Namespace) -> int:
    """Versions, compiler, cache folder, and what is compiled or falls back (exit 0)."""
    print("\n".join(report()))
    return 0


def add_parser(sub: argparse._SubParsersAction, parents: list) -> None:
    """Add ``doctor`` to the subparsers ``sub``."""
    p = sub.add_parser("doctor", parents=parents, help="versions, C compiler, cache folder, "
                       "and what is compiled or falls back")
    p.set_defaults(func=cmd_doctor)
