"""Planning in a cell: our proven planner against OMPL's RRTConnect + PathSimplifier and pyroboplan.

Four cells, the same Pinocchio + coal geometry for every planner (our CollisionChecker's
GeometryModel, its collision pairs):

* ``post``: zavar2024 swinging around a column and a wall (arm height);
* ``rack``: zavar2024 crossing low rack bars under its arms: only a lifted quill clears them;
* ``table``: zavar2024 over a cluttered table (tall and low parts);
* ``shelf``: a 6R arm (ur5_dh, capsules of 45 mm, joints within +-pi) at a shelf and a table.

Per cell, PAIRS start/goal pairs, both clear, whose straight joint segment collides (a dense
check at 1e-3 rad/m). Each planner gets a 1 s limit:

* **ours**: ``so.plan(robot, [PTP(goal)], start=, cell=checker)``: OMPL RRTConnect and
  PathSimplifier with every state and edge proven, toppra, the timed trajectory proven clear
  again. Timed from the call to the proven-clear, timed trajectory.
* **OMPL**: RRTConnect + ``PathSimplifier.simplify`` with a Python validity callback
  (Pinocchio's ``computeCollisions``) and edge resolution 0.01 (OMPL's discrete motion
  validator); plan and simplify timed separately.
* **pyroboplan** (optional: ``pip install pyroboplan``): RRTConnect (bidirectional) and
  ``shortcut_path``, its defaults (0.05 rad steps).

Every returned path is checked here, independently: configurations every 1e-3 rad (or m)
of joint motion along it (ours: along the timed trajectory), each asked of Pinocchio +
coal directly (``computeCollisions``, not our checker's batches, which may run our
compiled kernel). Printed per cell and overall: solved, colliding outputs (and the deepest overlap),
median times, median joint-space path lengths, and, on the side, one check's cost against
the raw ``computeCollisions`` call and the batch speedup over a loop.

Goals (issue 30): 0 colliding outputs; 100 % solved where OMPL solves; median time <= OMPL
RRTConnect + simplifier; >= 5x faster than pyroboplan; path length <= OMPL's simplified.

Run: ``python benchmarks/bench_plan.py`` (``--pairs N`` per cell, default 250; ``--quick``
for 20).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import math
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

import scara_opt as so
from scara_opt.errors import NoPathFoundError, TrajectoryError
from scara_opt.planning.ompl_backend import box_space, start_and_goal

TIME_LIMIT = 1.0
DENSE = 1e-3  # rad or m of joint motion between the independent checks
DATA = Path(__file__).resolve().parent.parent / "tests" / "data"


# ---------------------------------------------------------------------------- cells
def cells() -> dict[str, tuple[so.Robot, so.Cell, dict]]:
    """The four cells: robot, cell and the checker's keyword arguments."""
    scara = so.load_robot("zavar2024")
    post = so.Cell([so.Cylinder("column", 0.03, 0.4, xyz=(0.28, 0.12, 0.0)),
                    so.Box("wall", (0.12, 0.012, 0.4), xyz=(0.05, -0.3, 0.0), rpy=(0, 0, 0.4))],
                   name="post")
    bars = [so.Box(f"bar{k}", (0.012, 0.5, 0.03), xyz=(0.16 + 0.09 * k, 0.0, -0.09))
            for k in range(3)]
    rack = so.Cell(bars + [so.Box("bar_y", (0.3, 0.012, 0.03), xyz=(0.25, 0.22, -0.09))],
                   name="rack")
    parts = [so.Box("table", (0.9, 0.9, 0.02), xyz=(0.1, 0.0, -0.14)),
             so.Cylinder("tall1", 0.025, 0.3, xyz=(0.30, -0.12, 0.0)),
             so.Cylinder("tall2", 0.02, 0.3, xyz=(0.12, 0.30, 0.0)),
             so.Box("block", (0.06, 0.06, 0.05), xyz=(0.32, 0.12, -0.105)),
             so.Box("tray", (0.12, 0.08, 0.035), xyz=(0.18, -0.28, -0.112)),
             so.Sphere("ball", 0.025, xyz=(0.22, 0.05, -0.105)),
             so.Capsule("pipe", 0.012, 0.25, xyz=(-0.05, 0.3, -0.09), rpy=(0, 1.5708, 0.3))]
    table = so.Cell(parts, name="table")
    arm = so.Robot.from_urdf(DATA / "ur5_dh.urdf", tip="tool")
    arm = arm.with_limits(**{n: (-math.pi, math.pi) for n in arm.joint_names})
    shelf = so.Cell([so.Box("table", (1.4, 1.4, 0.04), xyz=(0.0, 0.0, -0.08)),
                     so.Box("shelf_low", (0.3, 0.8, 0.02), xyz=(0.55, 0.0, 0.25)),
                     so.Box("shelf_high", (0.3, 0.8, 0.02), xyz=(0.55, 0.0, 0.55)),
                     so.Box("side_l", (0.3, 0.02, 0.7), xyz=(0.55, 0.4, 0.35)),
                     so.Box("side_r", (0.3, 0.02, 0.7), xyz=(0.55, -0.4, 0.35)),
                     so.Box("back", (0.02, 0.8, 0.7), xyz=(0.71, 0.0, 0.35)),
                     so.Cylinder("post", 0.04, 0.8, xyz=(-0.35, 0.35, 0.4))], name="shelf")
    return {"post": (scara, post, {}), "rack": (scara, rack, {}), "table": (scara, table, {}),
            "shelf": (arm, shelf, {"radius": 0.045})}


def dense_polyline(Q: np.ndarray) -> np.ndarray:
    """Configurations every DENSE of joint motion along the polyline Q (its vertices too)."""
    rows = [Q[:1]]
    for a, b in zip(Q[:-1], Q[1:], strict=True):
        n = max(int(np.ceil(np.abs(b - a).max() / DENSE)), 1)
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
    """``n`` (start, goal) pairs: both clear, the straight segment through the cell."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.lower, robot.upper
    pairs = []
    while len(pairs) < n:
        Q = rng.uniform(lo, hi, (64, robot.nq))
        Q = Q[~checker.collides_many(Q)]
        for a, b in zip(Q[0::2], Q[1::2], strict=False):
            if len(pairs) < n and deepest(checker, dense_polyline(np.array([a, b]))):
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


def ours(robot: so.Robot, checker: so.CollisionChecker, a: np.ndarray, b: np.ndarray,
         seed: int) -> dict:
    PLANS.clear()
    t = time.perf_counter()
    try:
        traj = so.plan(robot, [so.PTP(b)], start=a, cell=checker, time_limit=TIME_LIMIT,
                       seed=seed)
    except (NoPathFoundError, TrajectoryError) as exc:
        return {"solved": False, "time": time.perf_counter() - t, "why": type(exc).__name__}
    elapsed = time.perf_counter() - t
    plan = PLANS[-1]
    Q = dense_trajectory(traj)
    return {"solved": True, "time": elapsed, "plan": plan.time_s,
            "simplify": elapsed - plan.time_s, "per_check": plan.time_s / max(plan.states, 1),
            "depth": deepest(checker, Q), "length": path_length(Q)}


def ompl_baseline(robot: so.Robot, checker: so.CollisionChecker, a: np.ndarray,
                  b: np.ndarray, seed: int) -> dict:
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


def pyroboplan_peer(robot: so.Robot, checker: so.CollisionChecker, a: np.ndarray,
                    b: np.ndarray, seed: int) -> dict:
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
def check_costs(robot: so.Robot, checker: so.CollisionChecker) -> tuple[float, float, float]:
    """Per configuration [us]: raw computeCollisions (on the checker's own model and data)
    and checker.collides (alternating on 500 configurations, the least of 9), and the batch
    of 10,000 vs a loop of collides (the speedup, the least of 5 each)."""
    rng = np.random.default_rng(0)
    Q = rng.uniform(robot.lower, robot.upper, (10_000, robot.nq))
    data, gdata, _ = checker._data()  # the raw call on the checker's own model and data
    model, gmodel = robot.model, checker.model
    raw, ours_, loop, batch = (math.inf,) * 4
    few = Q[:500]
    clock, compute, collides = time.perf_counter, pin.computeCollisions, checker.collides
    for _ in range(9):  # the two calls alternate on every configuration
        a = b = 0.0
        for q in few:
            t0 = clock()
            compute(model, data, gmodel, gdata, q, True)
            t1 = clock()
            collides(q)
            t2 = clock()
            a += t1 - t0
            b += t2 - t1
        raw, ours_ = min(raw, a / len(few)), min(ours_, b / len(few))
    for _ in range(5):
        t = time.perf_counter()
        for q in Q:
            checker.collides(q)
        loop = min(loop, (time.perf_counter() - t) / len(Q))
        t = time.perf_counter()
        checker.collides_many(Q)
        batch = min(batch, (time.perf_counter() - t) / len(Q))
    return raw * 1e6, ours_ * 1e6, loop / batch


def summary(rows: list[dict]) -> dict:
    solved = [r for r in rows if r["solved"]]
    bad = [r for r in solved if r["depth"] > 0]
    per = [r["per_check"] for r in solved if "per_check" in r]
    return {"solved": len(solved), "n": len(rows), "colliding": len(bad),
            "deepest_mm": max((r["depth"] for r in bad), default=0.0) * 1e3,
            "time_ms": float(np.median([r["time"] for r in rows])) * 1e3,
            "length": float(np.median([r["length"] for r in solved])) if solved else math.nan,
            "per_check_us": float(np.median(per)) * 1e6 if per else math.nan}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pairs", type=int, default=250, help="pairs per cell (250)")
    parser.add_argument("--quick", action="store_true", help="20 pairs per cell")
    parser.add_argument("--cells", default="post,rack,table,shelf")
    args = parser.parse_args()
    n = 20 if args.quick else args.pairs
    try:
        import pyroboplan  # noqa: F401
        peers = ["ours", "ompl", "pyroboplan"]
    except ImportError:
        print("pyroboplan not installed (pip install pyroboplan): its column is left out")
        peers = ["ours", "ompl"]
    run = {"ours": ours, "ompl": ompl_baseline, "pyroboplan": pyroboplan_peer}
    everything: dict[str, list[dict]] = {p: [] for p in peers}
    print(f"{n} pairs per cell, {TIME_LIMIT:g} s limit, independent check every {DENSE:g} "
          "rad/m; times are medians [ms]; ours: plan = the proven path (RRTConnect + "
          "simplifier), rest = toppra and the proof of the timed trajectory")
    print(f"{'cell':<7}{'planner':<12}{'solved':>9}{'colliding':>11}{'deepest':>10}"
          f"{'total':>8}{'plan':>8}{'rest':>8}{'length':>8}{'per check':>11}")
    built = cells()
    for name in args.cells.split(","):
        robot, cell, kw = built[name]
        checker = so.CollisionChecker(robot, cell, **kw)
        pairs = make_pairs(robot, checker, n, seed=7)
        raw, one, speedup = check_costs(robot, checker)
        for peer in peers:
            rows = [run[peer](robot, checker, a, b, seed) for seed, (a, b) in enumerate(pairs)]
            everything[peer] += rows
            s = summary(rows)
            solved = [r for r in rows if r["solved"]]
            plan = np.median([r["plan"] for r in solved]) * 1e3 if solved else math.nan
            rest = np.median([r["simplify"] for r in solved]) * 1e3 if solved else math.nan
            per = s["per_check_us"] / raw
            print(f"{name:<7}{peer:<12}{s['solved']:>5}/{s['n']:<3}{s['colliding']:>11}"
                  f"{s['deepest_mm']:>8.2f}mm{s['time_ms']:>8.1f}{plan:>8.1f}{rest:>8.1f}"
                  f"{s['length']:>8.3f}{per:>10.2f}x")
        print(f"{'':7}{checker.npairs} pairs; one check: raw computeCollisions {raw:.2f} us, "
              f"checker.collides {one:.2f} us ({one / raw:.2f}x); a batch of 10,000 "
              f"{speedup:.2f}x faster per configuration than the loop")
    print("\noverall")
    for peer in peers:
        s = summary(everything[peer])
        print(f"{'all':<7}{peer:<12}{s['solved']:>5}/{s['n']:<5}{s['colliding']:>9}"
              f"{s['deepest_mm']:>8.2f}mm{s['time_ms']:>8.1f}{'':16}{s['length']:>8.3f}")
    o, b = everything["ours"], everything["ompl"]
    ompl_solved = [(x, y) for x, y in zip(o, b, strict=True) if y["solved"]]
    print(f"\nsolved: ours {sum(x['solved'] for x in o)} of {len(o)} pairs, OMPL "
          f"{len(ompl_solved)}; of the {len(ompl_solved)} OMPL solves, ours solves "
          f"{sum(x['solved'] for x, _ in ompl_solved)}")
    t_o = np.median([x["time"] for x in o])
    t_b = np.median([y["time"] for y in b])
    print(f"median time, ours (plan to proven-clear timed trajectory) / OMPL (plan + "
          f"simplify): {t_o * 1e3:.1f} / {t_b * 1e3:.1f} ms = {t_o / t_b:.2f}")
    t_p = np.median([x["plan"] for x in o if x["solved"]])
    print(f"  ... ours' planning alone (the proven path, no timing): {t_p * 1e3:.1f} ms = "
          f"{t_p / t_b:.2f} of OMPL's")
    both = [(x, y) for x, y in zip(o, b, strict=True) if x["solved"] and y["solved"]]
    if both:
        ratio = np.median([x["length"] / y["length"] for x, y in both])
        print(f"median joint-space path length ratio ours / OMPL on pairs both solve "
              f"({len(both)}): {ratio:.3f}")
        clean = [(x, y) for x, y in both if y["depth"] == 0]
        if clean:
            print(f"  ... on pairs where OMPL's path is clear ({len(clean)}): "
                  f"{np.median([x['length'] / y['length'] for x, y in clean]):.3f}")
    if "pyroboplan" in everything:
        t_r = np.median([r["time"] for r in everything["pyroboplan"]])
        print(f"median time pyroboplan / ours: {t_r * 1e3:.1f} / {t_o * 1e3:.1f} ms = "
              f"{t_r / t_o:.2f}x")


if __name__ == "__main__":
    main()
