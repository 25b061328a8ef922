"""Motion programs: planning time of a 10-move program against raw toppra, and the 1 kHz check.

Prints, in one run (zavar2024, its own assumed limits, tool limits 0.5 m/s, 3 m/s²):

* ``so.plan`` of a 10-move program (PTP / LIN / CIRC, stop at each goal), median of
  REPEATS, split into the IK of the moves' points and the timing;
* raw toppra on the same joint paths (spline, joint velocity and acceleration constraints,
  the same grids, ``compute_parameterization``), median of REPEATS, and the ratio;
* the independent check (FK at 1 kHz, per move) of a trajectory of about 2 s.

Goals (issue 16): plan <= 50 ms; the 1 kHz check of a 2 s trajectory <= 20 ms.
"""

from __future__ import annotations

import math
import time

import numpy as np

import scara_opt as so
from scara_opt.motion.plan import move_joints
from scara_opt.motion.timing import MIN_GRID
from scara_opt.trajectory import resolve_limits
from scara_opt.trajectory.toppra_backend import chord_parameter

REPEATS = 7
START = np.array([-1.0, 1.15, 0.01, 0.0])


def program(robot: so.Robot) -> list:
    p = robot.position(START)
    return [so.LIN(p + [0, 0.1, 0], speed=0.3), so.CIRC(p + [0.05, 0.15, 0], p + [0, 0.2, 0]),
            so.LIN(p + [0, 0.2, -0.02]), so.LIN(p + [0, 0.2, 0]),
            so.PTP(so.Target(p + [-0.05, 0.3, 0])), so.LIN(p + [-0.05, 0.3, -0.03]),
            so.LIN(p + [-0.05, 0.3, 0], speed=0.2), so.CIRC(p + [0.03, 0.2, 0], p + [0, 0.1, 0]),
            so.PTP(so.Target(p + [0.02, 0.0, -0.01])), so.PTP(START)]


def blended(robot: so.Robot) -> list:
    """Ten LIN/CIRC moves blended at 10 mm, around a 0.1 x 0.2 m figure, back to the start."""
    p = robot.position(START)
    pts = [[0, 0.1, 0], [0, 0.2, 0], [-0.05, 0.2, 0], [-0.1, 0.2, 0], [-0.1, 0.1, 0],
           [-0.1, 0.0, 0], [-0.05, 0.0, 0], [-0.02, 0.0, 0], [0, 0.03, 0]]
    moves = [so.LIN(p + d, blend=0.01) for d in pts]
    moves[3] = so.CIRC(p + [-0.075, 0.22, 0], p + pts[3], blend=0.01)
    return moves + [so.LIN(p)]


def median_ms(fn, repeats: int = REPEATS) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return 1e3 * float(np.median(times))


def raw_toppra(paths: list[np.ndarray], vmax: np.ndarray, amax: np.ndarray) -> None:
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    for Q in paths:
        s = chord_parameter(Q, vmax)
        path = toppra.SplineInterpolator(s, Q)
        per = max(2, math.ceil(MIN_GRID / (len(Q) - 1)))  # as timing.time_section
        frac = np.arange(per) / per
        grid = np.append((s[:-1, None] + np.diff(s)[:, None] * frac).ravel(), s[-1])
        cons = [constraint.JointVelocityConstraint(vmax), constraint.JointAccelerationConstraint(
            amax, discretization_scheme=constraint.DiscretizationType.Interpolation)]
        algo.TOPPRA(cons, path, gridpoints=grid, solver_wrapper="seidel")\
            .compute_parameterization(0.0, 0.0)


def main() -> None:
    robot = so.load_robot("zavar2024")
    moves = program(robot)
    limits = so.ToolLimits(speed=0.5, acceleration=3.0)
    traj = so.plan(robot, moves, limits, start=START)  # warm-up (imports, compiled FK)
    t_plan = median_ms(lambda: so.plan(robot, moves, limits, start=START))

    def ik_only() -> list[np.ndarray]:
        q, out = START, []
        for i, m in enumerate(moves):
            Q = move_joints(i, m, robot, q, 0.002)
            out.append(Q)
            q = Q[-1]
        return out

    paths = ik_only()
    t_ik = median_ms(ik_only)
    lim = resolve_limits(robot, robot.nq)
    t_raw = median_ms(lambda: raw_toppra(paths, lim.vmax, lim.amax))
    print(f"10-move program: {sum(len(p) for p in paths)} joint points, duration "
          f"{traj.duration:.3f} s")
    print(f"  so.plan            {t_plan:8.1f} ms  (goal <= 50 ms)")
    print(f"    IK of the points {t_ik:8.1f} ms")
    print(f"    timing + checks  {t_plan - t_ik:8.1f} ms")
    print(f"  raw toppra (joint limits only, same paths and grids) {t_raw:8.1f} ms; "
          f"timing / raw = {(t_plan - t_ik) / t_raw:.2f}x, plan / raw = {t_plan / t_raw:.2f}x")
    smooth = blended(robot)
    one = so.plan(robot, smooth, limits, start=START)
    t_blend = median_ms(lambda: so.plan(robot, smooth, limits, start=START))
    from scara_opt.motion.blend import blended_joints
    from scara_opt.motion.plan import move_curve

    Qb, _, _ = blended_joints(list(enumerate(smooth)), robot, START, 0.002, move_curve)
    t_raw_b = median_ms(lambda: raw_toppra([Qb], lim.vmax, lim.amax))
    print(f"10-move blended program (10 mm radii, one toppra run of {len(Qb)} points): "
          f"{t_blend:.1f} ms (goal <= 50 ms), duration {one.duration:.3f} s; raw toppra on "
          f"the same joint path {t_raw_b:.1f} ms, plan / raw = {t_blend / t_raw_b:.2f}x")
    two = so.plan(robot, moves[:5], limits, start=START)
    t_check = median_ms(two.tool_limit_ratios)
    print(f"1 kHz tool check of a {two.duration:.2f} s trajectory: {t_check:.1f} ms "
          "(goal <= 20 ms)")


if __name__ == "__main__":
    main()
