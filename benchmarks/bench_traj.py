"""Trajectory timing: toppra and ruckig compute times, and durations against the shortest quintic.

Prints, in one run:

* toppra's compute time for a 100-waypoint path (zavar2024, an arc of the reachable circle
  on one elbow branch) — goal (issue 5): <= 50 ms;
* ruckig's compute time per trajectory (fang's two moves, point to point) and per
  segment of the 100-waypoint path;
* the wrappers against the raw libraries on the same input, in the same run (issue 18):
  ``time_parameterize(method="ruckig")`` against Ruckig's own ``calculate`` on fang's
  moves (goal <= 3x; and the floor through Ruckig's Python binding, objects made
  beforehand: positions set, ``calculate``, the phases read), ``method="toppra"`` against
  raw toppra (spline, the same two
  constraints and grid, ``compute_trajectory``) on the 100-waypoint arc (goal <= 1.2x);
* the durations of toppra and ruckig divided by the shortest quintic's (the baseline,
  computed in the same run under the same limits) on fang's moves (Tables 2-3), the
  zavar2024 circle of ten points (with its elbow flip) and the 100-waypoint arc.

All limits are the robots' own (assumed in robots/*.toml); ruckig's jerk = 10/s x amax.
"""

from __future__ import annotations

import math

import numpy as np
from timing import best_time

import scara_opt as so
from scara_opt import paths
from scara_opt.trajectory import ik_path, resolve_limits, time_parameterize
from scara_opt.trajectory.ruckig_backend import ruckig_segment
from scara_opt.trajectory.toppra_backend import OPTIONS, chord_parameter

REPEATS = 21


def best_ms(fn, *args, **kwargs) -> float:
    """:func:`timing.best_time` of REPEATS runs [ms]."""
    return best_time(fn, *args, repeats=REPEATS, **kwargs) * 1e3
N_WAYPOINTS = 100
DEG, MM = math.pi / 180, 1e-3
FANG_MOVES = {  # Tables 2 and 3, (deg, deg, mm, deg)
    "fang Table 2": ((0.0, 0.0, 0.0, -15.0), (-64.4042, 128.8085, 15.1500, -61.4099)),
    "fang Table 3": ((64.4042, 128.8085, 15.15, 61.4099), (-52.6250, -106.8207, 0.03, -52.7509)),
}
FANG_UNITS = np.array([DEG, DEG, MM, DEG])


def raw_ruckig(qa: np.ndarray, qb: np.ndarray, limits) -> object:
    """Ruckig's own calculation, inputs built beforehand: returns a timed ``calculate``."""
    import ruckig

    nq = len(qa)
    otg, inp, traj = ruckig.Ruckig(nq), ruckig.InputParameter(nq), ruckig.Trajectory(nq)
    inp.current_position, inp.target_position = list(qa), list(qb)
    inp.max_velocity, inp.max_acceleration = list(limits.vmax), list(limits.amax)
    inp.max_jerk = list(limits.jmax)
    inp.synchronization = ruckig.Synchronization.Time
    return lambda: otg.calculate(inp, traj)


def binding_floor(qa: np.ndarray, qb: np.ndarray, limits) -> object:
    """The least a wrapper must do through Ruckig's Python binding, objects made beforehand:
    set the two positions, ``calculate``, read every joint's phases (``t, j, a, v, p``)."""
    import ruckig

    nq = len(qa)
    otg, inp, traj = ruckig.Ruckig(nq), ruckig.InputParameter(nq), ruckig.Trajectory(nq)
    inp.max_velocity, inp.max_acceleration = list(limits.vmax), list(limits.amax)
    inp.max_jerk = list(limits.jmax)
    inp.synchronization = ruckig.Synchronization.Time
    a, b = qa.tolist(), qb.tolist()

    def run() -> object:
        inp.current_position, inp.target_position = a, b
        otg.calculate(inp, traj)
        return [(p.t, p.j, p.a, p.v, p.p) for p in traj.profiles[0]]
    return run


def raw_toppra(Q: np.ndarray, limits) -> object:
    """Raw toppra on our path and first grid: spline, constraints, ``compute_trajectory``."""
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    s = chord_parameter(Q, limits.vmax)
    per = max(OPTIONS["grid_per_segment"], math.ceil(OPTIONS["min_grid"] / (len(Q) - 1)))
    frac = np.arange(per) / per
    grid = np.append((s[:-1, None] + np.diff(s)[:, None] * frac).ravel(), s[-1])
    scale = 1.0 - OPTIONS["margin"]

    def run() -> object:
        path = toppra.SplineInterpolator(s, Q)
        cons = [constraint.JointVelocityConstraint(limits.vmax * scale),
                constraint.JointAccelerationConstraint(
                    limits.amax * scale,
                    discretization_scheme=constraint.DiscretizationType.Interpolation)]
        instance = algo.TOPPRA(cons, path, gridpoints=grid, solver_wrapper="seidel")
        return instance.compute_trajectory(0.0, 0.0)
    return run


def cases() -> dict[str, tuple[so.Robot, object]]:
    """The joint paths to time, by name: (robot, JointPath or (n, nq) array)."""
    fang = so.load_robot("fang")
    zavar = so.load_robot("zavar2024")
    out: dict[str, tuple[so.Robot, object]] = {
        name: (fang, np.array([a, b]) * FANG_UNITS) for name, (a, b) in FANG_MOVES.items()}
    out["zavar2024 circle, 10 pts"] = (zavar, ik_path(zavar, paths.zavar2024_circle(True)))
    arc = paths.circle((0.0, 0.0), 0.30, -0.07, N_WAYPOINTS, start=math.radians(151),
                       sweep=-math.radians(210))
    out[f"zavar2024 arc, {N_WAYPOINTS} pts"] = (zavar, ik_path(zavar, arc))
    return out


def main() -> None:
    table = cases()
    # warm-up: imports of toppra and ruckig, casadi caches
    for robot, path in table.values():
        for method in ("toppra", "ruckig"):
            time_parameterize(path, robot, method=method, allow_jumps=True)

    robot, arc = table[f"zavar2024 arc, {N_WAYPOINTS} pts"]
    t_toppra = best_ms(time_parameterize, arc, robot, method="toppra")
    t_ruckig_arc = best_ms(time_parameterize, arc, robot, method="ruckig")
    print(f"toppra, {N_WAYPOINTS}-waypoint path: {t_toppra:.1f} ms (goal <= 50 ms: "
          f"{'met' if t_toppra <= 50 else 'NOT met'})")
    print(f"ruckig, {N_WAYPOINTS}-waypoint path ({N_WAYPOINTS - 1} rest-to-rest segments): "
          f"{t_ruckig_arc:.1f} ms, {t_ruckig_arc / (N_WAYPOINTS - 1):.3f} ms per segment")
    for name in FANG_MOVES:
        robot, Q = table[name]
        full = best_ms(time_parameterize, Q, robot, method="ruckig")
        limits = resolve_limits(robot, robot.nq, need_jerk=True)
        raw = best_ms(ruckig_segment, Q[0], Q[1], limits)
        print(f"ruckig, {name} (one trajectory): {full:.3f} ms through time_parameterize, "
              f"{raw:.3f} ms for Ruckig's calculation and the conversion to polynomials")

    print("\nwrappers against the raw libraries, same input, same run:")
    arc_Q = arc.q if hasattr(arc, "q") else np.asarray(arc)
    raw = best_ms(raw_toppra(arc_Q, resolve_limits(robot, robot.nq)))
    ours = best_ms(time_parameterize, arc, robot, method="toppra")
    print(f"toppra, {N_WAYPOINTS}-waypoint arc: {ours:.2f} ms through time_parameterize, "
          f"{raw:.2f} ms raw toppra: {ours / raw:.2f}x (goal <= 1.2x: "
          f"{'met' if ours <= 1.2 * raw else 'NOT met'})")
    for name in FANG_MOVES:
        robot, Q = table[name]
        limits = resolve_limits(robot, robot.nq, need_jerk=True)
        raw = best_ms(raw_ruckig(Q[0], Q[1], limits))
        floor = best_ms(binding_floor(Q[0], Q[1], limits))
        ours = best_ms(time_parameterize, Q, robot, method="ruckig")
        print(f"ruckig, {name}: {ours:.3f} ms through time_parameterize, {raw:.4f} ms "
              f"Ruckig's calculate: {ours / raw:.0f}x (goal <= 3x: "
              f"{'met' if ours <= 3 * raw else 'NOT met'}); the binding's floor (positions "
              f"set, calculate, phases read) {floor / raw:.1f}x")

    print(f"\n{'path':<26}{'quintic [s]':>12}{'toppra [s]':>12}{'ruckig [s]':>12}"
          f"{'toppra/quintic':>16}{'ruckig/quintic':>16}")
    for name, (robot, path) in table.items():
        d = {m: time_parameterize(path, robot, method=m, allow_jumps=True).duration
             for m in ("quintic", "toppra", "ruckig")}
        print(f"{name:<26}{d['quintic']:>12.4f}{d['toppra']:>12.4f}{d['ruckig']:>12.4f}"
              f"{d['toppra'] / d['quintic']:>16.3f}{d['ruckig'] / d['quintic']:>16.3f}")
    print("(quintic stops at every waypoint; toppra and ruckig move through them, ruckig "
          "jerk-limited)")


if __name__ == "__main__":
    main()
