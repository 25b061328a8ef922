# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt[robots]"]
# ///
"""A Franka Panda as it ships in example-robot-data: IK, a time-optimal path, a pose drawing.

Needs: the ``robots`` extra, ``pip install "scara-opt[robots]"`` (the
``example-robot-data`` package: the Panda's URDF and meshes). Without it the script
stops at once with that instruction.

Shows that an arm a user already has loads without edits (issue 9): the Panda URDF is a
tree (arm, hand, two prismatic fingers, the right one a mimic joint) with ``package://``
meshes. ``Robot.from_urdf(path, tip="panda_hand_tcp")`` keeps the seven arm joints and
locks the fingers at zero.

* IK of a few reachable poses (drawn from seeded random joint values): IPOPT on the full
  pose (position and rotation, tol 1e-9), and the metaheuristic ``META`` on the same pose
  and on its position only, with the looser tolerance ``META_TOL`` that the metaheuristic
  literature uses.
* A time-optimal path (TOPP-RA) through the IPOPT solutions, within the URDF's velocity
  limits and Franka's published joint acceleration limits (``AMAX``; the URDF has none).
* The arm at the first solution, saved as ``examples/out/panda_pose.png``.

Needs the optional extra ``pip install 'scara-opt[robots]'`` (the example-robot-data
package); without it the script exits with a one-line message.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.model.catalogue import ROBOTS_EXTRA, example_robot_data_urdf
from scara_opt.plots import draw_robot

URDF = "panda_description/urdf/panda.urdf"  # below example-robot-data's robots/ folder
TIP = "panda_hand_tcp"
N_TARGETS = 3
TARGET_SEED = 2024  # joint values of the targets (not the solvers' seed)
SEED = 0
META = "pso"
META_TOL = 1e-3  # [m, rad]
#: Franka's published joint acceleration limits [rad/s²] (FCI documentation, "limits")
AMAX = (15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0)
#: Franka's "ready" pose [rad] (libfranka's examples; every joint inside its limits)
READY = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
TIMING = "toppra"
OUT = Path(__file__).resolve().parent / "out"


def load_panda() -> so.Robot:
    """The Panda from example-robot-data, or exit naming the extra to install."""
    try:
        path = example_robot_data_urdf(URDF)
    except ModuleNotFoundError:
        raise SystemExit(f"examples/panda.py needs example-robot-data: {ROBOTS_EXTRA}") from None
    return so.Robot.from_urdf(path, tip=TIP)


def targets(robot: so.Robot) -> list[so.Target]:
    """``N_TARGETS`` reachable poses: FK of seeded random joint values within the limits."""
    rng = np.random.default_rng(TARGET_SEED)
    Q = rng.uniform(robot.sampling_lower, robot.sampling_upper, (N_TARGETS, robot.nq))
    return [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in robot.fk_batch(Q)]


def ik_row(robot: so.Robot, k: int, target: so.Target, method: str,
           tol: float) -> so.IKResult:
    """Solve one target with one method and print one table row."""
    start = time.perf_counter()
    res = so.solve_ik(robot, target, method=method, seed=SEED, tol=tol)
    ms = (time.perf_counter() - start) * 1e3
    print(f"{k:>3} {method:>6} {target.kind:>9} {res.status.value:>10} {res.error:>10.2e} "
          f"{res.evaluations:>7} {ms:>9.1f}")
    return res


def solve_all(robot: so.Robot, poses: list[so.Target]) -> list[np.ndarray]:
    """IPOPT (and the metaheuristic, if registered) on every target; the IPOPT solutions."""
    meta = META in so.solvers()
    if not meta:
        print(f"(solver {META!r} is not registered: IPOPT only; registered: {so.solvers()})")
    print(f"{'#':>3} {'method':>6} {'task':>9} {'status':>10} {'error':>10} {'evals':>7} "
          f"{'time [ms]':>9}")
    solutions = []
    for k, target in enumerate(poses):
        solutions.append(ik_row(robot, k, target, "ipopt", 1e-9).q)
        if meta:
            ik_row(robot, k, target, META, META_TOL)
            ik_row(robot, k, so.Target(target.position), META, META_TOL)
    return solutions


def timed_path(robot: so.Robot, solutions: list[np.ndarray]) -> None:
    """Time the path from Franka's ready pose (``READY``) through each solution with ``TIMING``.

    (Zeros clipped into the limits put joint 4 on its upper limit, and toppra's spline
    through the waypoints then leaves it: refused, rightly.)
    """
    Q = np.vstack([READY, *solutions])
    traj = so.time_parameterize(Q, robot, method=TIMING, amax=np.array(AMAX))
    ratios = traj.check_limits()
    print(f"{TIMING} path through {len(Q)} waypoints: {traj.duration:.3f} s; largest "
          f"|qd|/vmax = {ratios['velocity'].max():.3f}, |qdd|/amax = "
          f"{ratios['acceleration'].max():.3f}")


def main() -> None:
    robot = load_panda()
    print(f"{robot}\nlocked: {robot.locked}")
    solutions = solve_all(robot, targets(robot))
    timed_path(robot, solutions)
    path = OUT / "panda_pose.png"
    draw_robot(robot, solutions[0], path=path, label="IPOPT solution of target 0")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
