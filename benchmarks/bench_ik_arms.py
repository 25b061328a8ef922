"""Full-pose IK on 6- and 7-joint arms, side by side with the peers, judged by one FK.

Arms: tests/data/ur5_dh.urdf (UR5-class 6R, standard DH) and tests/data/panda_dh.urdf
(Panda-class 7R, modified DH), plus example-robot-data's UR5 and Panda from their published
URDFs when that package is installed (``pip install "scara-opt[robots]"``; rtb loads the
same URDFs). Targets: 500 full poses per arm, FK of random in-limit configurations (seed 0).
Every method starts from the same q0 (mid-range of the limits). Success is judged by our
Pinocchio FK for every library alike: position < 1e-9 m (and 1e-6) AND rotation angle
< 1e-9 rad (and 1e-6) AND the joints within their limits; "flag lied" counts answers a
library called successful that fail this check at 1e-6.

Ours: ``solve_ik`` with ``lm``, ``auto`` and ``ipopt`` (``lm`` and ``auto`` take the arm's
closed form first where it serves, :mod:`scara_opt.ik.arm_route`; ``lm analytic=False``:
the descent alone); ``solve_many`` (time per target);
``lm`` and ``solve_many`` with ``nearest=False`` too, which stop at the first solution
reached, as ``ik_LM`` and TRAC-IK do (the default slides on to the one nearest ``q0``).
Peers, when installed (``pip install "scara-opt[bench]"``): roboticstoolbox ``ik_LM`` (C++,
tol 1e-19 since its residual is ½eᵀWe), TRAC-IK (pytracik, Speed, eps 1e-9, 5 ms), ik-geo
(analytic, the 6R cases it has a constructor for, built from our reading of the geometry:
the UR5s).

Prints the table and the goals of the arms issues: 100 % within 1e-9 for ``auto``; on a 6R
arm the closed form serves, ``lm`` and ``auto`` median per call at most half ``ik_LM``'s
(issue 40: "at least 2x faster"); on the 7R, ``lm`` (with and without ``nearest``) and
``auto`` at most ``ik_LM``'s; p95 <= 1 ms; ``solve_many``
per target at most half a ``solve_ik`` call (its total time over the targets against ``lm``'s
mean per call on the same targets: what looping ``solve_ik`` costs a target); the one-off
setup per robot and task kind (a fresh process: loading the compiled iterations from the
cache, or building them).
Times are wall clock on a shared machine: each target's least time over three passes
(``solve_many``: the least of three whole batches); compare within one run.

Then the path travel of issue 40 on the UR5 (example-robot-data's, else tests/data's): 10
sequences of 5 poses from configurations uniform in [-1.5, 1.5]^6, ``ik_path(robot,
targets, q_start=q[0])``: its joint travel [rad] (the step from ``q_start`` included) and
jumps against the sampled configurations' own (the default objective, least travel: never
more than the sampled sequence's), and with ``objective="fewest_jumps"``.

Usage: ``python benchmarks/bench_ik_arms.py [--quick]`` (``--quick``: 100 targets).
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pinocchio as pin
from timing import PASSES, best_time_and_result, least_per_call

import scara_opt as so
from scara_opt.ik.arm_geometry import arm_model
from scara_opt.model.catalogue import example_robot_data_urdf
from scara_opt.model.dh_file import load_dh
from scara_opt.trajectory.branches import travel_weights

DATA = Path(__file__).resolve().parent.parent / "tests" / "data"
N = 100 if "--quick" in sys.argv else 500
RTB_TOL = 1e-19  # their E = ½eᵀWe: 1e-19 reaches 1e-9 m on every SCARA target (1e-13: ~40 %)


def targets_of(robot: so.Robot, n: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """Configurations (n, nq) and their tip poses (4×4 each)."""
    Q = np.random.default_rng(0).uniform(robot.sampling_lower, robot.sampling_upper,
                                         (n, robot.nq))
    return Q, [robot.fk(q) for q in Q]


def check(robot: so.Robot, q: np.ndarray | None, T: np.ndarray) -> tuple[float, float]:
    """Position error [m] and rotation angle [rad] of ``q`` by our FK (inf if no answer or
    outside the limits)."""
    if q is None or not np.all(np.isfinite(q)) or not robot.within_limits(q, 1e-10):
        return np.inf, np.inf
    F = robot.fk(np.clip(q, robot.lower, robot.upper))
    return (float(np.linalg.norm(F[:3, 3] - T[:3, 3])),
            float(np.linalg.norm(pin.log3(T[:3, :3].T @ F[:3, :3]))))


def timed(solve: Callable[[int], tuple[np.ndarray | None, bool]], n: int) -> dict:
    """Per-target wall time [s] (:func:`timing.least_per_call`), answer and the library's
    own success flag."""
    times, out = least_per_call(solve, n)
    return {"t": times, "q": [q for q, _ in out], "flag": [flag for _, flag in out]}


#: our rows: label -> (method, options); "nearest=False" stops at the first solution
#: reached, as ik_LM and TRAC-IK do (the default slides on to the one nearest q0)
OURS = {"lm": ("lm", {}), "lm nearest=False": ("lm", {"nearest": False}),
        "lm analytic=False": ("lm", {"analytic": False}),
        "auto": ("auto", {}), "ipopt": ("ipopt", {})}


def ours(robot: so.Robot, poses: list[np.ndarray], q0: np.ndarray) -> dict[str, dict]:
    targets = [so.Target(T[:3, 3], rotation=T[:3, :3]) for T in poses]
    rows = {}
    for label, (method, options) in OURS.items():
        so.solve_ik(robot, targets[0], method=method, q0=q0, **options)  # setup untimed

        def solve(k: int, method: str = method, options: dict = options
                  ) -> tuple[np.ndarray, bool]:
            res = so.solve_ik(robot, targets[k], method=method, q0=q0, **options)
            return res.q, res.success

        rows[f"scara_opt {label}"] = timed(solve, len(targets))
    for suffix, nearest in (("", True), (" nearest=False", False)):
        so.solve_many(robot, targets[:4], q0s=q0, nearest=nearest)
        # the least of the passes' whole batches, as for the single calls
        t, batch = best_time_and_result(so.solve_many, robot, targets, q0s=q0,
                                        nearest=nearest, repeats=PASSES)
        rows[f"scara_opt solve_many{suffix} (per target)"] = {
            "t": np.full(len(targets), t / len(targets)), "q": list(batch.q),
            "flag": list(batch.success)}
    return rows


def rtb_robot(toml: Path, robot: so.Robot):
    """roboticstoolbox DHRobot from the same DH table (standard or modified), same limits;
    its tool is the constant transform (fixed rows, tool frame) that makes its FK at q = 0
    equal ours."""
    import roboticstoolbox as rtb

    dh = load_dh(toml)
    cls = rtb.RevoluteDH if dh.convention == "standard" else rtb.RevoluteMDH
    links = [cls(a=j.a, alpha=j.alpha, d=j.d, offset=j.theta, qlim=[j.lower, j.upper])
             for j in dh.joints if j.type == "revolute"]
    bare = rtb.DHRobot(links, name=dh.name)
    zero = np.zeros(robot.nq)
    tool = np.linalg.inv(bare.fkine(zero).A) @ robot.fk(zero)
    return rtb.DHRobot(links, name=dh.name, tool=tool)


def same_model(robot: so.Robot, fk: Callable[[np.ndarray], np.ndarray]) -> bool:
    """Whether a peer's FK equals ours (to 1e-9) on 5 random configurations: a peer row is
    shown only for the same model, so an adapter's mistake is never blamed on the peer."""
    Q = np.random.default_rng(99).uniform(robot.sampling_lower, robot.sampling_upper,
                                          (5, robot.nq))
    return all(np.abs(fk(q) - robot.fk(q)).max() < 1e-9 for q in Q)


def rtb_urdf(urdf: Path, tip: str):
    """roboticstoolbox's ETS of the chain to ``tip`` from the same URDF (its xacro loader
    told where example-robot-data's package:// paths point)."""
    import roboticstoolbox as rtb
    import xacrodoc.packages

    share = next((p for p in urdf.parents if p.name == "example-robot-data"), None)
    if share is not None:
        xacrodoc.packages.update_package_cache({"example-robot-data": str(share)})
    return rtb.Robot.URDF(str(urdf)).ets(end=tip)


def peers(robot: so.Robot, toml: Path | None, urdf: Path, poses: list[np.ndarray],
          q0: np.ndarray) -> dict[str, dict]:
    rows: dict[str, dict] = {}
    try:
        # the ETS (links and tool) of the DHRobot: DHRobot.ik_LM itself answers for a
        # different frame on the modified-DH Panda with a tool (0/100 there, success flags
        # set), while ETS.ik_LM solves the chain whose fkine we check
        E = rtb_robot(toml, robot).ets() if toml is not None else rtb_urdf(urdf, robot.tip)
    except ImportError:
        E = None
    if E is not None and not same_model(robot, lambda q: E.fkine(q).A):
        print(f"  (rtb: its model of {robot.name} differs from ours: no row)")
    elif E is not None:
        def rtb_solve(k: int) -> tuple[np.ndarray, bool]:
            sol = E.ik_LM(poses[k], q0=q0, tol=RTB_TOL, joint_limits=True)
            return np.asarray(sol.q, float), bool(sol.success)

        rows["rtb ik_LM (C++, tol 1e-19)"] = timed(rtb_solve, len(poses))
    try:
        import pytracik
    except ImportError:
        pytracik = None
    if pytracik is not None:
        solver = pytracik.TRAC_IK(_root_link(urdf), robot.tip, urdf.read_text(), 0.005, 1e-9,
                                  pytracik.Speed)

        def tracik_solve(k: int) -> tuple[np.ndarray | None, bool]:
            T = poses[k]
            x, y, z, w = pin.Quaternion(T[:3, :3]).coeffs()
            out = np.asarray(pytracik.ik(solver, q0, *T[:3, 3], x, y, z, w), float)
            ok = bool(out[0] > 0)  # pytracik returns (status, q...)
            return (out[1:] if ok else None), ok

        if same_model(robot, lambda q: np.asarray(pytracik.fk(solver, q))):
            rows["TRAC-IK Speed (pytracik, 5 ms)"] = timed(tracik_solve, len(poses))
        else:
            print(f"  (pytracik: its model of {robot.name} differs from ours: no row)")
    geo, M = _ik_geo(robot)
    if geo is not None:
        def geo_fk(q: np.ndarray) -> np.ndarray:
            R, p = geo.forward_kinematics(list(q))
            T = np.eye(4)  # ik-geo's R comes as the transpose of ours (nested lists)
            T[:3, :3], T[:3, 3] = np.asarray(R).T, np.ravel(p)
            return T @ M

        Minv = np.linalg.inv(M)

        def geo_solve(k: int) -> tuple[np.ndarray | None, bool]:
            G = poses[k] @ Minv  # its branches in (-pi, pi]: the nearest of those
            sols = [q for q, ls in geo.get_ik(G[:3, :3].T.tolist(), G[:3, 3].tolist())
                    if not ls]
            if not sols:
                return None, False
            return np.asarray(min(sols, key=lambda s: sum((a - b) ** 2 for a, b in
                                                         zip(s, q0, strict=True)))), True

        if not same_model(robot, geo_fk):
            print(f"  (ik-geo: its model of {robot.name} differs from ours: no row)")
        else:
            rows["ik-geo (analytic, nearest branch)"] = timed(geo_solve, len(poses))
    return rows


def _root_link(urdf: Path) -> str:
    import xml.etree.ElementTree as ET

    root = ET.fromstring(urdf.read_text())
    # top-level joints only (a <transmission> names joints too, without a child)
    children = {j.find("child").get("link") for j in root.findall("joint")}
    return next(lk.get("name") for lk in root.findall("link") if lk.get("name") not in children)


def _ik_geo(robot: so.Robot):
    """ik-geo's model of a 6R arm of the closed-form cases it has a constructor for, from
    our reading of the geometry (:mod:`scara_opt.ik.arm_geometry`: axes and offsets for the
    identity home, ``G = T M^-1``); ``(None, None)`` without ik-geo or such a case."""
    try:
        import ik_geo
    except ImportError:
        return None, None
    model = arm_model(robot)
    if model is None or model.held is not None or model.arm.reversed \
            or (model.arm.sign != 1).any():
        return None, None
    build = {"three_parallel_two_intersecting": ik_geo.Robot.three_parallel_two_intersecting,
             "spherical_two_intersecting": ik_geo.Robot.spherical_two_intersecting,
             "spherical_two_parallel": ik_geo.Robot.spherical_two_parallel}[model.arm.case]
    return build(model.arm.H.tolist(), model.arm.P.tolist()), model.home


def setup_cost(urdf: Path, tip: str) -> float:
    """One-off setup [s] of lm in a fresh process (loading or building the iterations)."""
    code = ("import time, numpy as np, scara_opt as so; "
            f"r = so.Robot.from_urdf({str(urdf)!r}, tip={tip!r}); q = np.zeros(r.nq); "
            "T = r.fk(q); res = so.solve_ik(r, so.Target(T[:3, 3], rotation=T[:3, :3]), "
            "method='lm'); print(res.setup_s)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    return float(out.stdout.strip().splitlines()[-1])


def report(label: str, robot: so.Robot, poses: list[np.ndarray], rows: dict[str, dict]) -> None:
    base = rows.get("rtb ik_LM (C++, tol 1e-19)")
    base_med = float(np.median(base["t"])) if base else None
    print(f"\n{label}: {len(poses)} full-pose targets, q0 = mid-range; judged by our FK")
    print(f"  {'method':<48} {'@1e-6':>7} {'@1e-9':>7} {'lied':>5} {'median':>10} "
          f"{'p95':>10} {'x ik_LM':>8}")
    stats = {}
    for name, row in rows.items():
        errs = [check(robot, q, T) for q, T in zip(row["q"], poses, strict=True)]
        e = np.array([max(a, b) for a, b in errs])
        lied = sum(1 for f, err in zip(row["flag"], e, strict=True) if f and err > 1e-6)
        med, p95 = float(np.median(row["t"])), float(np.percentile(row["t"], 95))
        stats[name] = (float(np.mean(e <= 1e-9)), med, p95)
        ratio = f"{med / base_med:8.2f}" if base_med else f"{'-':>8}"
        print(f"  {name:<48} {np.mean(e <= 1e-6):7.1%} {np.mean(e <= 1e-9):7.1%} {lied:5d} "
              f"{med * 1e3:7.3f} ms {p95 * 1e3:7.3f} ms {ratio}")
    auto_rate, auto_med, auto_p95 = stats["scara_opt auto"]
    lm_med = stats["scara_opt lm"][1]
    many = stats["scara_opt solve_many (per target)"][1]
    lm_mean = float(np.mean(rows["scara_opt lm"]["t"]))
    fast_many = stats["scara_opt solve_many nearest=False (per target)"][1]
    fast_mean = float(np.mean(rows["scara_opt lm nearest=False"]["t"]))
    print(f"  goals: auto 100 % @1e-9: {auto_rate:.1%} "
          f"({'met' if auto_rate == 1.0 else 'NOT met'}); p95 <= 1 ms: auto {auto_p95 * 1e3:.2f}"
          f" ms ({'met' if auto_p95 <= 1e-3 else 'NOT met'}); solve_many <= half a call "
          f"(rule: its time per target over lm's mean per call, the same targets): "
          f"{many / lm_mean:.2f} ({'met' if many <= lm_mean / 2 else 'NOT met'}; over lm's "
          f"median: {many / lm_med:.2f}); nearest=False: {fast_many / fast_mean:.2f} "
          f"({'met' if fast_many <= fast_mean / 2 else 'NOT met'})")
    if base_med:
        served = arm_model(robot) is not None
        goal = 0.5 if robot.nq == 6 else 1.0
        rule = (f"issue 40, {'6R' if robot.nq == 6 else '7R'} arm the closed form serves: "
                f"<= {goal:g}x" if served else "no closed form: <= 1x")
        goal = goal if served else 1.0
        parts = []
        for name in ("lm", "lm nearest=False", "auto"):
            r = stats[f"scara_opt {name}"][1] / base_med
            ok = r <= goal and stats[f"scara_opt {name}"][0] == 1.0
            parts.append(f"{name} {r:.2f}x ({'met' if ok else 'NOT met'})")
        print(f"         median against ik_LM's ({rule}, at 100 % @1e-9): " + ", ".join(parts))


def path_travel(robot: so.Robot, label: str, n: int = 10) -> None:
    """Issue 40's path experiment: ik_path's joint travel against the sampled sequence's."""
    w = travel_weights(robot)
    thr = np.full(robot.nq, np.pi / 2)

    def measure(Q: np.ndarray, q_start: np.ndarray) -> tuple[float, float, int, float]:
        D = np.abs(np.diff(np.vstack([q_start, Q]), axis=0))
        return (float(D.sum()), float((D @ w).sum()), int((D[1:] > thr).any(axis=1).sum()),
                float(D.max()))

    print(f"\n{label}: ik_path over {n} sequences of 5 poses (configurations uniform in "
          "[-1.5, 1.5]^6, q_start = the first); travel [rad] incl. the step from q_start, "
          "jumps (a joint > pi/2 in one step), largest step [rad]; the default objective "
          "is 'travel' (weighted by 1/vmax [s]), 'fewest_jumps' puts the jumps first")
    print(f"  {'seq':>3} {'sampled':>24} {'ik_path (default)':>26} {'fewest_jumps':>26}"
          f" {'time':>8}")
    more = more_w = more_fj = 0
    totals = np.zeros(3)
    times = []
    for s in range(n):
        Q = np.random.default_rng(s).uniform(-1.5, 1.5, (5, robot.nq))
        targets = [so.Target(robot.fk(q)) for q in Q]
        t = time.perf_counter()
        path = so.ik_path(robot, targets, q_start=Q[0])
        times.append(time.perf_counter() - t)
        fj = so.ik_path(robot, targets, q_start=Q[0], objective="fewest_jumps")
        a, b, c = measure(Q, Q[0]), measure(path.q, Q[0]), measure(fj.q, Q[0])
        totals += (a[0], b[0], c[0])
        more += b[0] > a[0] + 1e-9
        more_w += b[1] > a[1] + 1e-9
        more_fj += c[0] > a[0] + 1e-9
        row = [f"{m[0]:6.2f} rad {m[2]} jumps {m[3]:4.2f}" for m in (a, b, c)]
        print(f"  {s:>3} {row[0]:>24} {row[1]:>26} {row[2]:>26} {times[-1] * 1e3:6.1f} ms"
              + ("" if path.solved.all() else "  (not all solved)"))
    print(f"  mean travel: sampled {totals[0] / n:.2f} rad, ik_path {totals[1] / n:.2f} rad, "
          f"fewest_jumps {totals[2] / n:.2f} rad; more travel than the sampled sequence: "
          f"default {more_w}/{n} in weighted travel (goal 0), {more}/{n} in rad; "
          f"fewest_jumps {more_fj}/{n} in rad; ik_path median {np.median(times) * 1e3:.1f} ms")


def main() -> None:
    arms = [("UR5-class 6R (tests/data)", DATA / "ur5_dh.urdf", "tool", DATA / "ur5_dh.toml"),
            ("Panda-class 7R (tests/data)", DATA / "panda_dh.urdf", "tool",
             DATA / "panda_dh.toml")]
    try:
        arms += [("UR5 (example-robot-data URDF)",
                  example_robot_data_urdf("ur_description/urdf/ur5_robot.urdf"), "tool0", None),
                 ("Panda (example-robot-data URDF)",
                  example_robot_data_urdf("panda_description/urdf/panda.urdf"), "panda_hand",
                  None)]
    except ModuleNotFoundError:
        print("(example-robot-data not installed: its UR5 and Panda are left out; "
              "pip install 'scara-opt[robots]')")
    for label, urdf, tip, toml in arms:
        robot = so.Robot.from_urdf(urdf, tip=tip)
        q0 = 0.5 * (robot.sampling_lower + robot.sampling_upper)
        _, poses = targets_of(robot, N)
        rows = ours(robot, poses, q0)
        rows.update(peers(robot, toml, urdf, poses, q0))
        report(label, robot, poses, rows)
        print(f"  one-off setup in a fresh process (lm, full pose): "
              f"{setup_cost(urdf, tip) * 1e3:.1f} ms (goal <= 50 ms, or cached across processes)")
    label, urdf, tip, _ = arms[2] if len(arms) > 2 else arms[0]
    path_travel(so.Robot.from_urdf(urdf, tip=tip), label)


if __name__ == "__main__":
    main()
