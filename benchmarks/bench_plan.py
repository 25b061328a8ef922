"""Planning in a cell, per robot: our proven planner against OMPL's RRTConnect + simplifier.

Robots and cells (benchmarks/plan_cells.py says each): three SCARAs of different sizes and
base placements (zavar2024, an IRB-910SC-like 0.30 + 0.25 m arm off the origin, a 1 m-reach
SCARA) each in a post, a rack and an STL-fixture cell; a UR5-class arm of capsules, and
example-robot-data's UR5 and Panda from their published URDFs with their own collision
meshes, each in a table-and-box, a shelf and an STL-fixture cell. Every planner works on the
same Pinocchio + coal geometry: our CollisionChecker's GeometryModel and its pairs (a base
mounted 3 mm into its table: that pair left out, as found by the checker).

Per cell, PAIRS start/goal pairs, both clear, whose straight joint segment collides, each
with a known free path (through a third configuration; independent dense checks). Each
planner gets a 1 s limit:

* **ours**: ``so.plan(robot, [PTP(goal)], start=, cell=checker, time_limit=1)``: OMPL
  RRTConnect and the simplifier with every state and edge proven, toppra, the timed
  trajectory proven clear again; timed from the call to the proven-clear, timed trajectory.
  Its overshoot: the call's time beyond the limit.
* **OMPL**: RRTConnect + ``PathSimplifier.simplify`` (1 s) with a Python validity callback
  (Pinocchio's ``computeCollisions``, its default requests) and edge resolution 0.01
  (OMPL's discrete motion validator); plan and simplify timed.
* **pyroboplan** (``--pyroboplan``; ``pip install pyroboplan``): RRTConnect and
  ``shortcut_path``.

Every returned path is checked here, independently of our kernel: configurations every
1e-3 rad (or m) of joint motion along it (ours: along the timed trajectory), each asked of
Pinocchio + coal directly with fresh requests (a contact: ``computeCollisions`` with coal's
contact computation, or a signed distance <= 0; the depth from ``computeDistances``).
Printed: per cell and per robot, solved, colliding outputs (and the deepest), median times,
median path lengths; one check's cost against the raw ``computeCollisions``.

Goals (issue 37): per robot, 100 % solved where OMPL solves; median time <= OMPL's
(aim: half); 0 colliding; the time limit kept (overshoot: the final timing and proof).

Run: ``python benchmarks/bench_plan.py`` (``--pairs N`` per cell, default 100; ``--quick``
for 10; ``--robots zavar2024,ur5`` to choose).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import math
import time
import warnings

import numpy as np
import pinocchio as pin
from plan_cells import Bench, benches

import scara_opt as so
from scara_opt.errors import NoPathFoundError, TrajectoryError
from scara_opt.planning.ompl_backend import box_space, start_and_goal

TIME_LIMIT = 1.0
DENSE = 1e-3  # rad or m of joint motion between the independent checks


# ---------------------------------------------------------------------------- checks
def dense_polyline(Q: np.ndarray, step: float = DENSE) -> np.ndarray:
    """Configurations every ``step`` of joint motion along the polyline Q (its vertices too)."""
    rows = [Q[:1]]
    for a, b in zip(Q[:-1], Q[1:], strict=True):
        n = max(int(np.ceil(np.abs(b - a).max() / step)), 1)
        rows.append(a + np.linspace(0.0, 1.0, n + 1)[1:, None] * (b - a))
    return np.vstack(rows)


def deepest(checker: so.CollisionChecker, Q: np.ndarray) -> float:
    """0 if every configuration of Q (n, nq) is clear, else the deepest overlap [m] (> 0).

    By Pinocchio's own calls on the checker's model (computeCollisions, then
    computeDistances where in contact): independent of scara_opt's compiled kernel, which
    the checker's batches may use.
    """
    model, gmodel = checker.robot.model, checker.model
    data, gdata = model.createData(), pin.GeometryData(gmodel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        for req in gdata.collisionRequests:
            req.enable_cached_gjk_guess = False
            req.enable_contact = True
        for req in gdata.distanceRequests:
            req.enable_cached_gjk_guess = False
    hit = [q for q in Q if pin.computeCollisions(model, data, gmodel, gdata, q, True)]
    if not hit:
        return 0.0
    depth = 0.0
    for q in hit:
        pin.computeDistances(model, data, gmodel, gdata, q)
        depth = max(depth, -min(r.min_distance for r in gdata.distanceResults))
    return max(depth, 1e-12)


def dense_trajectory(traj: so.Trajectory) -> np.ndarray:
    """The trajectory sampled so no joint moves more than DENSE between samples."""
    dt = DENSE / max(float(traj.peaks()["velocity"].max()), 1e-9)
    t = np.append(np.arange(0.0, traj.duration, dt), traj.duration)
    return traj.evaluate(t)


def path_length(Q: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(Q, axis=0), axis=1).sum())


def make_pairs(robot: so.Robot, checker: so.CollisionChecker, n: int, seed: int) -> list:
    """``n`` (start, goal) pairs, each with a known collision-free path.

    Both ends clear, the straight segment between them through the cell, and a third
    configuration ``c`` with the segments start-c and c-goal both clear: first by the
    checker's batch on the dense samples, then confirmed by the independent :func:`deepest`.
    """
    rng = np.random.default_rng(seed)
    lo, hi = robot.lower, robot.upper

    def clear(a: np.ndarray, b: np.ndarray) -> bool:  # coarse samples first: most hit
        for step in (20 * DENSE, DENSE):
            if checker.collides_many(dense_polyline(np.array([a, b]), step)).any():
                return False
        return True

    pairs: list = []
    while len(pairs) < n:
        Q = rng.uniform(lo, hi, (96, robot.nq))
        Q = Q[~checker.collides_many(Q)]
        for a, b, c in zip(Q[0::3], Q[1::3], Q[2::3], strict=False):
            if len(pairs) == n or clear(a, b) or not (clear(a, c) and clear(c, b)):
                continue
            if deepest(checker, dense_polyline(np.array([a, b]))) and not deepest(
                    checker, dense_polyline(np.array([a, c, b]))):
                pairs.append((a, b))
    return pairs


# ---------------------------------------------------------------------------- planners
PLANS: list = []  # the PathPlan of each of our queries (its time and counts)


def _recording(plan_path):
    def wrapped(*args, **kwargs):
        res = plan_path(*args, **kwargs)
        PLANS.append(res)
        return res
    return wrapped


clearance_module = importlib.import_module("scara_opt.motion.clearance")
clearance_module.plan_path = _recording(clearance_module.plan_path)


def ours(bench: Bench, checker: so.CollisionChecker, a: np.ndarray, b: np.ndarray,
         seed: int) -> dict:
    PLANS.clear()
    t = time.perf_counter()
    try:
        traj = so.plan(bench.robot, [so.PTP(b)], start=a, cell=checker, time_limit=TIME_LIMIT,
                       seed=seed, **bench.plan)
    except (NoPathFoundError, TrajectoryError) as exc:
        return {"solved": False, "time": time.perf_counter() - t, "why": type(exc).__name__}
    elapsed = time.perf_counter() - t
    plan = PLANS[-1]
    Q = dense_trajectory(traj)
    return {"solved": True, "time": elapsed, "plan": plan.time_s,
            "simplify": elapsed - plan.time_s, "per_check": plan.time_s / max(plan.states, 1),
            "depth": deepest(checker, Q), "length": path_length(Q), "cut": "time limit" in
            plan.message}


def ompl_baseline(bench: Bench, checker: so.CollisionChecker, a: np.ndarray,
                  b: np.ndarray, seed: int) -> dict:
    robot = bench.robot
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util as ou

    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(seed + 1)
    nq = robot.nq
    space = box_space(ob, robot.lower, robot.upper)
    si = ob.SpaceInformation(space)
    model, gmodel = robot.model, checker.model
    data, gdata = model.createData(), pin.GeometryData(gmodel)
    q = np.zeros(nq)
    idx = range(nq)
    calls = [0]

    def valid(s: object) -> bool:
        calls[0] += 1
        q[:] = [s[i] for i in idx]
        return not pin.computeCollisions(model, data, gmodel, gdata, q, True)

    si.setStateValidityChecker(valid)
    si.setStateValidityCheckingResolution(0.01)
    si.setup()
    pdef = start_and_goal(ob, space, si, a, b)
    planner = og.RRTConnect(si)
    planner.setProblemDefinition(pdef)
    planner.setup()
    t = time.perf_counter()
    status = planner.solve(ob.timedPlannerTerminationCondition(TIME_LIMIT))
    t_plan = time.perf_counter() - t
    if str(status) != "Exact solution":
        return {"solved": False, "time": t_plan, "plan": t_plan, "simplify": 0.0}
    path = pdef.getSolutionPath()
    t = time.perf_counter()
    og.PathSimplifier(si).simplify(path, TIME_LIMIT)
    t_simp = time.perf_counter() - t
    Q = np.array([[path.getState(i)[k] for k in idx] for i in range(path.getStateCount())])
    return {"solved": True, "time": t_plan + t_simp, "plan": t_plan, "simplify": t_simp,
            "per_check": (t_plan + t_simp) / calls[0],
            "depth": deepest(checker, dense_polyline(Q)),
            "length": path_length(Q)}


def pyroboplan_peer(bench: Bench, checker: so.CollisionChecker, a: np.ndarray,
                    b: np.ndarray, seed: int) -> dict:
    robot = bench.robot
    from pyroboplan.planning.path_shortcutting import shortcut_path
    from pyroboplan.planning.rrt import RRTPlanner, RRTPlannerOptions

    options = RRTPlannerOptions(rrt_connect=True, bidirectional_rrt=True,
                                max_planning_time=TIME_LIMIT, rng_seed=seed)
    planner = RRTPlanner(robot.model, checker.model, options=options)
    t = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()):  # it prints "Planning timed out"
        path = planner.plan(a, b)
    t_plan = time.perf_counter() - t
    if path is None or len(path) == 0:  # [] when it runs out of time
        return {"solved": False, "time": t_plan, "plan": t_plan, "simplify": 0.0}
    t = time.perf_counter()
    path = shortcut_path(robot.model, checker.model, path)
    t_simp = time.perf_counter() - t
    Q = np.array(path)
    return {"solved": True, "time": t_plan + t_simp, "plan": t_plan, "simplify": t_simp,
            "depth": deepest(checker, dense_polyline(Q)), "length": path_length(Q)}


# ---------------------------------------------------------------------------- side numbers
def check_costs(robot: so.Robot, checker: so.CollisionChecker) -> tuple[float, float]:
    """Per configuration [us]: Pinocchio's raw ``computeCollisions`` (on the checker's own
    model and data) and ``checker.collides``, alternating on 500 random configurations, the
    least of 5 passes each."""
    Q = np.random.default_rng(0).uniform(robot.lower, robot.upper, (500, robot.nq))
    data, gdata, _ = checker._data()
    model, gmodel = robot.model, checker.model
    raw = ours_ = math.inf
    clock, compute, collides = time.perf_counter, pin.computeCollisions, checker.collides
    for _ in range(5):
        a = b = 0.0
        for q in Q:
            t0 = clock()
            compute(model, data, gmodel, gdata, q, True)
            t1 = clock()
            collides(q)
            t2 = clock()
            a += t1 - t0
            b += t2 - t1
        raw, ours_ = min(raw, a / len(Q)), min(ours_, b / len(Q))
    return raw * 1e6, ours_ * 1e6


def summary(rows: list[dict]) -> dict:
    solved = [r for r in rows if r["solved"]]
    bad = [r for r in solved if r["depth"] > 0]
    return {"solved": len(solved), "n": len(rows), "colliding": len(bad),
            "deepest_mm": max((r["depth"] for r in bad), default=0.0) * 1e3,
            "time_ms": float(np.median([r["time"] for r in rows])) * 1e3,
            "length": float(np.median([r["length"] for r in solved])) if solved else math.nan}


def _row(label: str, peer: str, rows: list[dict]) -> str:
    s = summary(rows)
    solved = [r for r in rows if r["solved"]]
    plan = np.median([r["plan"] for r in solved]) * 1e3 if solved else math.nan
    rest = np.median([r["simplify"] for r in solved]) * 1e3 if solved else math.nan
    return (f"{label:<26}{peer:<11}{s['solved']:>5}/{s['n']:<4}{s['colliding']:>9}"
            f"{s['deepest_mm']:>8.2f}mm{s['time_ms']:>8.1f}{plan:>8.1f}{rest:>8.1f}"
            f"{s['length']:>8.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pairs", type=int, default=100, help="pairs per cell (100)")
    parser.add_argument("--quick", action="store_true", help="10 pairs per cell")
    parser.add_argument("--robots", default="", help="robots to run (default: all)")
    parser.add_argument("--cells", default="", help="cells to run (default: all)")
    parser.add_argument("--pyroboplan", action="store_true", help="also pyroboplan")
    args = parser.parse_args()
    n = 10 if args.quick else args.pairs
    peers = ["ours", "ompl"] + (["pyroboplan"] if args.pyroboplan else [])
    run = {"ours": ours, "ompl": ompl_baseline, "pyroboplan": pyroboplan_peer}
    by_robot: dict[str, dict[str, list[dict]]] = {}
    print(f"{n} pairs per cell, {TIME_LIMIT:g} s limit, independent check every {DENSE:g} "
          "rad/m; times are medians [ms]: total, plan (ours: the proven path), rest (ours: "
          "toppra and the proof; OMPL: the simplifier)")
    print(f"{'robot / cell':<26}{'planner':<11}{'solved':>10}{'colliding':>9}{'deepest':>10}"
          f"{'total':>8}{'plan':>8}{'rest':>8}{'length':>8}")
    chosen = set(filter(None, args.robots.split(",")))
    cells = set(filter(None, args.cells.split(",")))
    for bench in benches():
        if (chosen and bench.robot_name not in chosen) or (cells and bench.cell_name not in
                                                           cells):
            continue
        checker = so.CollisionChecker(bench.robot, bench.cell, **bench.checker)
        pairs = make_pairs(bench.robot, checker, n, seed=7)
        ours(bench, checker, *pairs[0], seed=10**6)  # untimed: the first call's one-off costs
        raw, one = check_costs(bench.robot, checker)
        label = f"{bench.robot_name} / {bench.cell_name}"
        for peer in peers:
            rows = [run[peer](bench, checker, a, b, seed) for seed, (a, b) in enumerate(pairs)]
            by_robot.setdefault(bench.robot_name, {}).setdefault(peer, []).extend(rows)
            print(_row(label, peer, rows), flush=True)
        print(f"{'':26}{checker.npairs} pairs; one check: raw computeCollisions {raw:.2f} us, "
              f"checker.collides {one:.2f} us ({one / raw:.2f}x)", flush=True)
    print("\nper robot")
    for name, rows in by_robot.items():
        for peer in peers:
            print(_row(name, peer, rows[peer]))
        o, b = rows["ours"], rows["ompl"]
        ompl_solved = [x for x, y in zip(o, b, strict=True) if y["solved"]]
        t_o, t_b = np.median([x["time"] for x in o]), np.median([y["time"] for y in b])
        over = max(x["time"] - TIME_LIMIT for x in o)
        both = [(x, y) for x, y in zip(o, b, strict=True) if x["solved"] and y["solved"]]
        ratio = np.median([x["length"] / y["length"] for x, y in both]) if both else math.nan
        print(f"{name:<26}ours solves {sum(x['solved'] for x in ompl_solved)} of the "
              f"{len(ompl_solved)} OMPL solves ({sum(x['solved'] for x in o)} of {len(o)} in "
              f"all); median time {t_o * 1e3:.1f} / {t_b * 1e3:.1f} ms = {t_o / t_b:.2f} of "
              f"OMPL's; path length {ratio:.3f} of OMPL's; longest call {TIME_LIMIT + over:.3f}"
              f" s ({over * 1e3:+.0f} ms over the limit); simplifier cut by the limit in "
              f"{sum(x.get('cut', False) for x in o)}")


if __name__ == "__main__":
    main()
