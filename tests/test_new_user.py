"""The rough edges a new user hit (issue 31), one test each, driven as that user drove them."""

from __future__ import annotations

import re

import numpy as np
import pytest

import scara_opt as so


def test_nguyen_cycle_strokes_up_against_gravity_and_across_level(robots):
    """nguyen's robot file puts base z up: the 25 mm strokes go along +z, the 305 mm level.

    Before: its 25 mm "up/down" strokes were along -y (horizontal) and the 305 mm "across"
    along z (vertical), because the cycle followed the revolute axis, horizontal on nguyen.
    The vertical SCARAs keep their placement (zavar2024: 2.2303 s). Mutations caught: the
    strokes along the axis again (``Au, Bu = A + up * UP, ...`` -> ``A + up * n``) and the
    across stroke across the ray (``w = np.cross(g.n, u) if vertical else level`` ->
    ``np.cross(g.n, u)``: vertical on nguyen), each fails.
    """
    robot = robots["nguyen"]
    res = so.cycle_time(robot)
    steps = np.diff(robot.positions(res.corners), axis=0)
    np.testing.assert_allclose(steps[[0, 3]], [[0, 0, 0.025]] * 2, atol=1e-9)  # up
    np.testing.assert_allclose(steps[[2, 5]], [[0, 0, -0.025]] * 2, atol=1e-9)  # down
    for k in (1, 4):  # across: level, 305 mm
        assert abs(steps[k, 2]) < 1e-9 and np.linalg.norm(steps[k]) == pytest.approx(0.305)
    zavar = so.cycle_time(robots["zavar2024"])
    assert zavar.durations["toppra"] == pytest.approx(2.2303, abs=1e-4)


def test_a_blend_of_exactly_half_the_stroke_is_allowed(robots):
    """peng2025's cycle, whose 25 mm strokes measure 0.024999999999999994 m by FK: blend
    0.0125 m (half) plans; 0.0126 m is refused naming a value that is itself allowed.

    Before: 0.0125 refused with "pass blend <= 0.0125". Mutation caught: no round-off
    allowance (``radius > half * (1.0 + BLEND_SLACK)`` -> ``radius > half``) -> refused,
    fails.
    """
    robot = robots["peng2025"]
    res = so.cycle_time(robot, blend=0.0125)
    assert res.durations["toppra_blended"] < res.durations["toppra"]
    with pytest.raises(so.errors.InputError) as info:
        so.cycle_time(robot, blend=0.0126)
    allowed = float(str(info.value).rsplit("<= ", 1)[1])
    assert allowed == 0.0125 and so.cycle_time(robot, blend=allowed).blend == allowed


def test_errors_quote_the_users_units(tmp_path, capsys):
    """What the user gave in mm or degrees comes back in mm or degrees.

    Before: ``cycle --blend 50`` answered "move 0: blend radius 0.05 m ... pass blend <=
    0.0125"; ``ik --yaw 1e9`` quoted 17453292.5 rad; a TOML in degrees with lower 130 >
    upper 120 quoted 2.2689 and 2.0944. Mutations caught: the CLI's blend check dropped
    (``check_cycle_blend(...)`` removed from cmd_cycle) -> metres; ``--yaw``
    parsed as a plain float -> radians; the file's limits not checked in its units
    (``_check_limits(...)`` removed) -> radians; each fails.
    """
    from scara_opt import cli

    assert cli.main(["cycle", "zavar2024", "--blend", "50"]) == 2
    err = capsys.readouterr().err
    assert "--blend 50 mm" in err and "pass --blend <= 12.5" in err and "move 0" not in err
    assert cli.main(["ik", "zavar2024", "--xyz", "-230", "200", "-70", "--mm", "--yaw",
                     "1e9"]) == 2
    err = capsys.readouterr().err
    assert "1e9 deg" in err and "rad" not in err
    text = (so.model.dh_file.bundled_dir() / "zavar2024.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("lower = -120\n", "lower = 130\n", 1))
    assert cli.main(["fk", str(bad), "0", "0", "0", "0"]) == 2
    err = capsys.readouterr().err
    assert "lower limit 130 deg is not below upper limit 120 deg" in err


def test_csv_columns_are_t_q_qd_qdd_as_the_docs_and_json_say(robots, tmp_path):
    """to_csv writes t, then q, qd, qdd (each over every joint), the order of to_json.

    Before: the docs said "t, q, qd, qdd" while the header interleaved each joint's q, qd,
    qdd. Mutation caught: the per-joint interleaving back (``cols, header = [t, q, qd, qdd],
    ...`` -> the old loop) -> fails.
    """
    import json

    robot = robots["fang"]
    traj = so.time_parameterize([[0, 0, 0, 0], [0.5, -0.4, 0.02, 1.0]], robot)
    path = traj.to_csv(tmp_path / "t.csv", dt=0.01)
    header = path.read_text().splitlines()[0].split(",")
    names, units = robot.joint_names, ["rad", "rad", "m", "rad"]
    expected = ["t_s"] + [f"{n}_{u}{s}" for s in ("", "_per_s", "_per_s2")
                          for n, u in zip(names, units, strict=True)]
    assert header == expected
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    doc = json.loads(so.motion.export.to_json(traj, tmp_path / "t.json", dt=0.01).read_text())
    flat = np.column_stack([doc["t_s"], doc["q"], doc["qd"], doc["qdd"]])
    np.testing.assert_allclose(data, flat, rtol=1e-9, atol=1e-12)


def test_summarize_reports_the_success_rate_compare_judged(robots):
    """summarize(df) uses the table's own verdict: one table, one success rate.

    Before: summarize defaulted to tol 1e-6 whatever tol compare had judged at (1e-9 by
    default), so solves with errors between the two counted as reached in one and missed
    in the other. Here compare judges at 1e-3. Mutation caught: the default back to 1e-6
    (``tol: float | None = None`` -> ``1e-6``) -> the rates differ, fails.
    """
    robot = robots["zavar2024"]
    table = so.compare(robot, [[-0.23, 0.20, -0.07]], methods=["pso", "fa"], populations=[20],
                       iterations=40, seeds=range(6), progress=False, reference=False,
                       tol=1e-3)
    between = (table["error"] > 1e-6) & (table["error"] <= 1e-3)
    assert between.any()  # else the test could not tell the two rates apart
    summary = so.comparison.summarize(table)
    rate = table.groupby("method", sort=False)["success"].mean()
    np.testing.assert_allclose(summary.set_index("method")["within_tol"], rate[summary.method])
    strict = so.comparison.summarize(table, tol=1e-6)
    assert (strict["within_tol"] <= summary["within_tol"]).all()


def test_readme_pso_example_shows_what_it_claims(capsys):
    """The README's ``ik ... --method pso`` line, run as printed: solved at its --tol, exit 0.

    Before: it exited 1 (``max_iter``, residual 2.6e-7 at the default tol 1e-9) under a
    heading of working examples. Mutation caught: the README line without ``--tol 1e-6``
    -> exit 1, fails.
    """
    import json
    import shlex

    from scara_opt import cli
    from tests.conftest import ROOT

    line = next(raw for raw in (ROOT / "README.md").read_text().splitlines()
                if raw.startswith("scara-opt ik zavar2024") and "--method pso" in raw)
    argv = shlex.split(line.split("#")[0])[1:]
    assert cli.main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "solved" and 1e-9 < out["error"] <= 1e-6


def test_cycle_plot_title_fits_and_says_the_times(monkeypatch, tmp_path):
    """cycle --plot's title: the robot, strokes and each time, within the figure's width.

    Before: ``f"{robot.name}: {res!r}"``, a Python repr cut at both ends of the figure.
    Mutation caught: that title back in cmd_cycle -> wider than the figure, fails.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from scara_opt import cli

    seen = {}

    def capture(robot, traj, path, title=""):
        seen["title"] = title
        return path

    monkeypatch.setattr("scara_opt.motion.plot.plot_motion", capture)
    assert cli.main(["cycle", "zavar2024", "--blend", "10", "--plot", "--out",
                     str(tmp_path / "c")]) == 0
    title = seen["title"]
    assert "CycleResult(" not in title and "zavar2024" in title and "toppra_blended" in title
    fig = plt.figure(figsize=(8, 8), dpi=110)
    text = fig.suptitle(title)
    fig.canvas.draw()
    box = text.get_window_extent()
    assert box.x0 >= 0 and box.x1 <= fig.bbox.width
    plt.close(fig)


def test_compare_yaw_error_is_a_float_column(robots):
    """compare's yaw_error: float, NaN for a position-only target (it has no tool angle).

    Before: an object column holding None. Mutation caught: ``res.yaw_error`` stored as it
    is -> object dtype, fails.
    """
    robot = robots["zavar2024"]
    table = so.compare(robot, [[-0.23, 0.20, -0.07], [0.3, 0.1, -0.07]], methods=["lm"],
                       progress=False, reference=False)
    assert table["yaw_error"].dtype == np.float64 and table["yaw_error"].isna().all()
    mixed = so.compare(robot, [[-0.23, 0.20, -0.07], so.Target([-0.23, 0.20, -0.07], yaw=0.5)],
                       methods=["lm"], progress=False, reference=False)
    assert np.isnan(mixed["yaw_error"][0]) and np.isfinite(mixed["yaw_error"][1])


def test_blended_moves_end_among_the_waypoint_times(robots):
    """A blended cycle's waypoint_times: every move's end, the blended ones where the tip
    passes closest to the corner, moving; the stops apart in ``stops``.

    Before: only the three stops (0, the place, the return). Mutation caught: the passages
    not added (``traj.with_corner_passages()`` -> ``traj`` in plan) -> 3 times, fails.
    """
    robot = robots["zavar2024"]
    traj = so.cycle_time(robot, blend=0.01).trajectory
    assert len(traj.waypoint_times) == 7 and len(traj.stops) == 3
    assert np.all(np.diff(traj.waypoint_times) > 0)
    assert set(traj.stops) <= set(traj.waypoint_times)
    passing = [t for t in traj.waypoint_times if t not in set(traj.stops)]
    P = robot.positions(traj.evaluate(np.array(passing)))
    corners = np.array([c for c, _, _ in traj.corners])
    np.testing.assert_allclose(np.linalg.norm(P - corners, axis=1), traj.blend_deviations(),
                               atol=1e-9)
    assert (np.linalg.norm(traj.evaluate(np.array(passing), 1), axis=1) > 0.05).all()
    np.testing.assert_allclose(traj.evaluate(traj.waypoint_times), traj.waypoints, atol=1e-12)


def test_tool_limits_are_each_moves_and_no_limit_reads_none(robots):
    """traj.tool_limits: one per move, its own; a ToolProfile shows "none", not 1e+12.

    Before: a blended run of a 1 m/s LIN and a 0.5 m/s LIN reported 0.5 m/s for both
    (the run's tightest), and the profile printed 1e+12 for "no limit". Mutations caught:
    the run's tightest back -> (0.5,), fails; ``math.inf`` -> ``UNLIMITED`` in
    ToolProfile.per_point -> "1e+12 m/s²" printed, fails.
    """
    from scara_opt.motion import LIN, plan

    robot = robots["zavar2024"]
    q0 = np.array([-1.0, 1.15, 0.01, 0.0])
    p = robot.position(q0)
    traj = plan(robot, [LIN(p + [0, 0.1, 0], speed=1.0, blend=0.02),
                        LIN(p + [0, 0.2, 0], speed=0.5)], start=q0)
    assert [t.speed for t in traj.tool_limits] == [1.0, 0.5]
    text = repr(traj.profiles[0][1])
    assert "1e+12" not in text and "acceleration none" in text and "1 m/s on" in text


def test_docstring_math_keeps_its_parentheses_and_is_typeset():
    """:math: roles become arithmatex LaTeX, whole; mkdocs.yml loads KaTeX from the repo.

    Before: the API pages showed LaTeX as inline code (arithmatex with neither MathJax nor
    KaTeX), and 8 inline formulas lost their closing parenthesis (``U(0, 1``: the role's
    target had ``rstrip("()")`` applied, as for ``:func:`f()```). Mutation caught: math
    through the cross-reference path again (``MATH.sub(...)`` dropped) -> inline code,
    stripped, fails.
    """
    import yaml  # mkdocs' own dependency

    from tests.conftest import ROOT
    from tests.test_docs import _roles

    roles = _roles()
    assert roles.convert(r"with :math:`r \sim U(0, 1)` per leap") == (
        r"with \(r \sim U(0, 1)\) per leap")
    assert roles.convert(":math:`a = a_0 (1 - (t + 1)/T)`") == r"\(a = a_0 (1 - (t + 1)/T)\)"
    config = yaml.load((ROOT / "mkdocs.yml").read_text(), Loader=yaml.BaseLoader)
    assets = config["extra_javascript"] + config["extra_css"]
    assert any("katex.min.js" in a for a in assets)
    for asset in assets:
        assert (ROOT / "docs" / asset).is_file(), asset
    css = (ROOT / "docs" / "javascripts" / "katex" / "katex.min.css").read_text()
    fonts = {f for f in re.findall(r"url\((fonts/[^)]+\.woff2)\)", css)}
    assert fonts and all((ROOT / "docs" / "javascripts" / "katex" / f).is_file() for f in fonts)
