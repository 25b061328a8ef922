"""Workspace: Monte Carlo area against the analytic area, reachability against IPOPT, footprint."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import scara_opt as so
from scara_opt.footprint import Footprint
from scara_opt.model.dh import DHJoint, DHRobot
from scara_opt.workspace_analysis import Workspace, workspace

L = 0.2  # link lengths of the planar test arm [m]
SHOULDER = math.radians(90)  # |theta1| <= 90 deg: span D = 180 deg
ELBOW = math.radians(120)  # |theta2| <= 120 deg = c


def planar_2r() -> so.Robot:
    """Planar 2R arm, l1 = l2 = L, theta1 in [-90, 90] deg, theta2 in [-120, 120] deg."""
    return so.Robot.from_dh(DHRobot("planar2r", (
        DHJoint("theta1", "revolute", a=L, lower=-SHOULDER, upper=SHOULDER),
        DHJoint("theta2", "revolute", a=L, lower=-ELBOW, upper=ELBOW),
    )))


def planar_2r_area(link: float, span: float, c: float) -> float:
    """Analytic area [m²] reached by a planar 2R arm (derivation below).

    Arm: l1 = l2 = l = ``link`` [m], shoulder range of width ``span``, elbow range [-c, c]
    [rad]; valid for c <= span and span + c <= 2 pi.

    At radius r the elbow angle is ±g with r = 2 l cos(g/2), and the tip lies at the polar
    angle theta1 ± g/2 (the arm's triangle is isosceles), so the polar angles reached at r
    are two arcs of length ``span`` offset by ±g/2: they overlap (g <= c <= span) and do
    not wrap around (span + c <= 2 pi), covering span + g. The region is therefore

    * the annular sector r in [r_min, r_max], r_max = 2 l, r_min = 2 l cos(c/2), of angle
      ``span``: area span (r_max² - r_min²) / 2;
    * plus a cap at each end of the shoulder range: the points beyond the end ray, up to
      the arc the tip traces as the elbow opens from 0 to c with the shoulder at its limit.
      With the base O at the origin and the elbow E at (l, 0), the cap is the forearm's
      circular sector about E (area l² c / 2) plus the triangle O, E, tip(c) (area
      l² sin(c) / 2) minus the inner disc's sector over the tip's polar angle c/2
      (area r_min² c / 4 = l² c cos²(c/2)): cap = (l² / 2) (sin c - c cos c).

    A = span (r_max² - r_min²) / 2 + l² (sin c - c cos c).
    (Check: integrating r (span + g(r)) dr over [r_min, r_max] gives the same.)
    """
    r_max, r_min = 2 * link, 2 * link * math.cos(c / 2)
    return span * (r_max**2 - r_min**2) / 2 + link**2 * (math.sin(c) - c * math.cos(c))


@pytest.fixture(scope="module")
def zavar_ws(robots) -> Workspace:
    return workspace(robots["zavar2024"], n=60_000, seed=0)


def test_mc_area_of_a_planar_2r_arm_matches_the_analytic_area():
    """At N = 60,000 the grid area of a 2R arm with joint limits is within 2% of the formula."""
    exact = planar_2r_area(L, 2 * SHOULDER, ELBOW)
    assert exact == pytest.approx(0.26502, abs=1e-5)
    robot = planar_2r()
    for seed in range(3):
        ws = workspace(robot, n=60_000, seed=seed)
        assert ws.xy_area == pytest.approx(exact, rel=0.02)
    # a fixed cell size converges too, and more samples get closer
    assert workspace(robot, n=60_000, grid=0.01).xy_area == pytest.approx(exact, rel=0.02)
    assert workspace(robot, n=240_000).xy_area == pytest.approx(exact, rel=0.005)


def test_planar_2r_ranges_and_closed_form_contains():
    """The 2R arm's radial range is [2l cos(c/2), 2l]; contains is exact at sampled tips."""
    robot = planar_2r()
    ws = workspace(robot, n=60_000)
    assert ws.contains_method == "closed_form"
    lo, hi = ws.radial_range
    assert lo == pytest.approx(2 * L * math.cos(ELBOW / 2), abs=2e-4)
    assert hi == pytest.approx(2 * L, abs=2e-4)
    assert ws.contains(ws.points[:2000]).all()
    far = np.array([[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.3, 0.0, 0.01], [-0.3, -0.05, 0.0]])
    assert not ws.contains(far).any()


def test_contains_agrees_with_ipopt_on_1000_random_points(robots, zavar_ws):
    """contains() matches IPOPT's solved/unreachable on 1000 random points of the bounding box.

    IPOPT's "solved" is its own (the residual is recomputed from the FK); its "unreachable"
    is confirmed by the scalar closed form (ik_all), the vectorised one is under test here.
    About 15 s: half of the points are out of reach and cost IPOPT 11 starts each.
    """
    robot = robots["zavar2024"]
    lo, hi = zavar_ws.bounds
    P = np.random.default_rng(7).uniform(lo, hi, (1000, 3))
    inside = zavar_ws.contains(P)
    status = [str(so.solve_ik(robot, p, method="ipopt", tol=1e-9).status) for p in P]
    assert set(status) <= {"solved", "unreachable"}, "IPOPT missed a reachable point"
    solved = np.array(status) == "solved"
    assert 0.2 < inside.mean() < 0.8  # both verdicts are exercised
    np.testing.assert_array_equal(inside, solved)


def test_zavar2024_paper_targets(zavar_ws):
    """The paper's target (-0.23, 0.20, -0.20) is out of reach (z); (-0.23, 0.20, -0.07) is in."""
    inside = zavar_ws.contains([[-0.23, 0.20, -0.20], [-0.23, 0.20, -0.07]])
    assert inside.tolist() == [False, True]


def test_zavar2024_ranges(zavar_ws):
    """Radius in [0.2, 0.4] m (the inner hole of Fig. 3), z in [-0.098, -0.05] m, all kept."""
    assert zavar_ws.points.shape == (60_000, 3) and zavar_ws.q.shape == (60_000, 4)
    assert zavar_ws.n_dropped == 0 and zavar_ws.footprint is None
    np.testing.assert_allclose(zavar_ws.radial_range, (0.2, 0.4), atol=1e-4)
    np.testing.assert_allclose(zavar_ws.z_range, (-0.098, -0.05), atol=1e-4)
    assert zavar_ws.height_range == zavar_ws.z_range
    np.testing.assert_allclose(zavar_ws.bounds[:, 2], zavar_ws.z_range)
    assert zavar_ws.plane.labels == ("x", "y", "z")


def test_grid_contains_approximates_the_closed_form(zavar_ws):
    """The grid route agrees with the exact one away from the boundary (>= 97% of points)."""
    grid_ws = dataclasses.replace(zavar_ws, contains_method="grid")
    P = np.random.default_rng(3).uniform(*zavar_ws.bounds, (20_000, 3))
    agree = (grid_ws.contains(P) == zavar_ws.contains(P)).mean()
    assert agree > 0.97


def test_grid_area_matches_the_closed_form_area(zavar_ws):
    """The grid area is within 1% of zavar2024's area counted by the closed form on a lattice."""
    lo, hi = zavar_ws.bounds
    u, v = np.meshgrid(np.linspace(lo[0], hi[0], 800), np.linspace(lo[1], hi[1], 800))
    P = np.column_stack([u.ravel(), v.ravel(), np.full(u.size, -0.07)])
    exact = zavar_ws.contains(P).mean() * (hi[0] - lo[0]) * (hi[1] - lo[1])
    assert zavar_ws.xy_area == pytest.approx(exact, rel=0.01)


def test_same_seed_gives_the_same_points(robots):
    """Same seed, same samples; another seed, other samples."""
    robot = robots["fang"]
    a, b = workspace(robot, n=500, seed=3), workspace(robot, n=500, seed=3)
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.q, b.q)
    assert a.xy_area == b.xy_area
    assert not np.array_equal(a.points, workspace(robot, n=500, seed=4).points)


@pytest.mark.parametrize("name", ["fang", "nguyen", "inverted5"])
def test_samples_are_numpys_uniform_draws(robots, name):
    """The samples are ``default_rng(seed).uniform(lower, upper, (n, nq))`` bit for bit
    (workspace draws them in one block and scales in place, for speed).

    Mutations caught: the offset dropped (``out += lo``); the range taken as ``hi`` alone.
    """
    robot = robots[name]
    ws = workspace(robot, n=2000, seed=5, footprint=False)
    expected = np.random.default_rng(5).uniform(robot.sampling_lower, robot.sampling_upper,
                                                (2000, robot.nq))
    np.testing.assert_array_equal(ws.q, expected)


def test_samples_are_within_limits_and_match_fk(robots):
    """Samples lie within the joint limits and points are their FK positions."""
    robot = robots["inverted5"]
    ws = workspace(robot, n=1000, seed=1)
    assert robot.within_limits(ws.q).all()
    np.testing.assert_allclose(ws.points, robot.positions(ws.q), atol=1e-15)


# ---------------------------------------------------------------------- footprint (peng2025)
def test_peng2025_footprint_limits_the_elbow_to_120_degrees(robots):
    """The base footprint drops exactly the samples with |theta2| > 120 deg (Fig. 5-6).

    Mutation caught: the segment test's squared distance compared with the radius, not its
    square (``_segment_within``, shared by the kernel and the chain test).
    """
    robot = robots["peng2025"]
    free = workspace(robot, n=60_000, seed=0, footprint=False)
    calibrated = workspace(robot, n=60_000, seed=0)
    assert calibrated.footprint is not None and free.footprint is None
    # link 2 passes at L1 sin|theta2| from the circle's centre (the shoulder axis)
    fp = calibrated.footprint
    np.testing.assert_allclose(fp.center, [0.12, 0.0])
    limit = math.pi - math.asin(fp.radius / 0.22)
    assert math.degrees(limit) == pytest.approx(120.0, abs=0.01)
    kept = np.abs(free.q[:, 2]) < limit
    assert calibrated.points.shape[0] == kept.sum() == 60_000 - calibrated.n_dropped
    np.testing.assert_array_equal(calibrated.q, free.q[kept])
    # the calibrated workspace is the workspace of a robot whose elbow stops at 120 deg
    limited = robot.with_limits(theta2=(-math.radians(120), math.radians(120)))
    ref = workspace(limited, n=60_000, seed=1, footprint=False)
    assert calibrated.xy_area == pytest.approx(ref.xy_area, rel=0.02)
    assert calibrated.xy_area < 0.8 * free.xy_area
    # the tip no longer comes near the shoulder axis: r >= |J1 -> tip| at 120 deg
    nearest = math.sqrt(0.22**2 + 0.2**2 + 2 * 0.22 * 0.2 * math.cos(limit))
    assert calibrated.radial_range[0] == pytest.approx(nearest, abs=1e-3)


def test_peng2025_contains_respects_the_footprint(robots):
    """Closed-form contains with the footprint equals contains of the 120-deg-elbow robot."""
    robot = robots["peng2025"]
    calibrated = workspace(robot, n=2000)
    free = workspace(robot, n=2000, footprint=False)
    limited = workspace(robot.with_limits(theta2=(-math.radians(120), math.radians(120))),
                        n=2000, footprint=False)
    P = np.random.default_rng(5).uniform(*free.bounds, (20_000, 3))
    inside = calibrated.contains(P)
    np.testing.assert_array_equal(inside, limited.contains(P))
    assert (free.contains(P) & ~inside).sum() > 1000  # points only the folded elbow reached
    assert not (inside & ~free.contains(P)).any()


def test_footprint_columns_give_the_plane_coordinates_answers(robots):
    """``blocks_arms`` of a circle (the plane's columns point by point, views of the world
    columns where the plane's axes are world axes) answers as ``blocks`` of the full plane
    coordinates, on peng2025's chains, in its own plane, one with a reversed axis and a
    tilted one.

    Mutations caught: u and v swapped in ``Plane.columns``; the view taken for a reversed
    axis too (``world_axis``: ``e[k[0]] == 1.0`` -> ``abs(e[k[0]]) == 1.0``).
    """
    from scara_opt.workspace_analysis import Plane, workspace_plane

    robot = robots["peng2025"]
    zone, plane = Footprint.from_robot(robot), workspace_plane(robot)
    Q = np.random.default_rng(6).uniform(robot.sampling_lower, robot.sampling_upper,
                                         (5000, robot.nq))
    chain = robot.joint_origins(Q)
    s = math.sqrt(0.5)
    planes = [plane, Plane(-plane.e1, plane.e2, -plane.n, plane.origin, ("u", "v", "h")),
              Plane(np.array([s, 0.0, s]), plane.e2, np.array([-s, 0.0, s]), plane.origin,
                    ("u", "v", "h"))]
    for p in planes:
        expected = zone.blocks(p.coords(chain), zone.first_origin(robot))
        assert 100 < expected.sum() < 4900  # both answers occur
        np.testing.assert_array_equal(zone.blocks_arms(robot, p, chain), expected)


@pytest.mark.parametrize("links_from", ["theta2", None])  # None: a circle off the base
def test_the_circle_kernel_answers_as_the_chain_test(robots, links_from):
    """``Footprint.kernel`` (the circle's test compiled with the FK, which ``workspace``
    uses) gives ``robot.positions`` bit for bit and ``blocks_arms``' verdict on the chains
    of joint origins, on 20,000 peng2025 samples, in its plane and in a tilted one.

    Mutations caught: the kernel's first rows the last joint origin instead of the tip;
    the clip of the nearest point dropped from the casadi ops; the checked
    points from one later (``[first:]`` -> ``[first + 1:]``); the world-axis shortcut of
    ``_sx_along`` taking another entry (``point[axis - 1]``).
    """
    from scara_opt.model import batch_fk
    from scara_opt.workspace_analysis import Plane, workspace_plane

    robot = robots["peng2025"]
    own = Footprint.from_robot(robot)
    zone = own if links_from else Footprint("circle", center=[0.35, 0.1], radius=0.08)
    plane = workspace_plane(robot)
    s = math.sqrt(0.5)
    tilted = Plane(np.array([s, 0.0, s]), plane.e2, np.array([-s, 0.0, s]), plane.origin,
                   ("u", "v", "h"))
    Q = np.random.default_rng(8).uniform(robot.sampling_lower, robot.sampling_upper,
                                         (20_000, robot.nq))
    chain = robot.joint_origins(Q)
    for p in (plane, tilted):
        rows = batch_fk.evaluate_function(robot, zone.kernel(robot, p), Q)
        np.testing.assert_array_equal(rows[:, :3], robot.positions(Q))
        expected = zone.blocks_arms(robot, p, chain)
        assert 100 < expected.sum() < 19_900  # both answers occur
        np.testing.assert_array_equal(rows[:, 3] == 1.0, expected)
    assert Footprint("polygon", vertices=[[0, 0], [1, 0], [0, 1]]).kernel(robot, plane) is None


def test_polygon_footprint_blocks_crossing_segments():
    """A segment with both ends outside a polygon but crossing it blocks; one beside it does not."""
    square = Footprint("polygon", vertices=[[-1, -1], [1, -1], [1, 1], [-1, 1]])
    chains = np.array([
        [[-2.0, 0.0], [2.0, 0.0]],  # crosses through
        [[-2.0, 2.0], [2.0, 2.0]],  # passes above
        [[0.5, 0.5], [3.0, 3.0]],  # starts inside
        [[3.0, 0.0], [3.0, 0.0]],  # a point outside
    ])
    assert square.blocks(chains).tolist() == [True, False, True, False]
    circle = Footprint("circle", center=[0.0, 0.0], radius=1.0)
    assert circle.blocks(chains).tolist() == [True, False, True, False]


def test_polygon_footprint_reproduces_the_circle(robots):
    """A 72-gon circumscribing peng2025's circle drops almost the same samples."""
    robot = robots["peng2025"]
    fp = Footprint.from_robot(robot)
    k = 72
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    rad = fp.radius / math.cos(math.pi / k)
    poly = Footprint("polygon", vertices=fp.center + rad * np.column_stack([np.cos(t), np.sin(t)]),
                     links_from="theta2")
    a, b = workspace(robot, n=20_000, footprint=fp), workspace(robot, n=20_000, footprint=poly)
    assert b.n_dropped >= a.n_dropped
    assert b.n_dropped - a.n_dropped < 0.01 * 20_000


def test_malformed_footprint_tables_raise_urdf_error(robots):
    """A [footprint] table with a bad shape, size, key or joint name is refused, naming it."""
    base = robots["peng2025"]
    cases = [
        ({"shape": "hexagon"}, "shape"),
        ({"shape": "circle", "center": [120, 0], "radius": -1}, "radius"),
        ({"shape": "circle", "center": [120], "radius": 10}, "center"),
        ({"shape": "polygon", "vertices": [[0, 0], [1, 0]]}, "3 vertices"),
        ({"shape": "circle", "center": [0, 0], "radius": 1, "colour": "red"}, "unknown keys"),
        ({"shape": "circle", "center": [0, 0], "radius": 1, "links_from": "elbow"}, "elbow"),
    ]
    for table, match in cases:
        robot = base.with_limits()
        robot.metadata = {**base.metadata, "footprint": table}
        with pytest.raises(so.URDFError, match=match):
            workspace(robot, n=100)


# ---------------------------------------------------------------------- redundant robots: grid
def test_nguyen_uses_the_grid_in_its_plane_of_motion(robots):
    """nguyen moves in x-z (yaw axis -y): the grid decides; its own samples are inside."""
    ws = workspace(robots["nguyen"], n=20_000)
    assert ws.contains_method == "grid"
    assert ws.plane.labels == ("x", "z", "-y")
    np.testing.assert_allclose(ws.height_range, (0.08, 0.18), atol=1e-4)  # -py = d4 + d5
    assert ws.contains(ws.points).all()
    outside = ws.points[:100] + np.array([0.0, -0.5, 0.0])  # beyond the d4 stroke
    assert not ws.contains(outside).any()
    assert not ws.contains([[0.0, -0.1, 5.0]]).any()


def test_inverted5_uses_the_grid(robots):
    """inverted5's redundant P1/P5 pair: the grid decides, and reach is r <= 2 L from J1."""
    ws = workspace(robots["inverted5"], n=20_000)
    assert ws.contains_method == "grid"
    reach = 2 * 7.87 * 0.0254
    assert 0.99 * reach < ws.radial_range[1] <= reach + 1e-12
    assert ws.contains(ws.points[:500]).all()


# ---------------------------------------------------------------------- plots
@pytest.mark.parametrize("name", ["peng2025", "nguyen"])
def test_plots_are_written_as_png(robots, tmp_path, name):
    """plot_xy and plot_3d write PNG files and return their paths."""
    ws = workspace(robots[name], n=3000)
    for path in (ws.plot_xy(tmp_path / "xy.png"), ws.plot_3d(tmp_path / "cloud.png")):
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_paths_are_checked(robots, tmp_path):
    """A non-PNG name or a missing folder is an InputError saying what to do."""
    ws = workspace(robots["zavar2024"], n=100)
    with pytest.raises(so.InputError, match=".png"):
        ws.plot_xy(tmp_path / "xy.pdf")
    with pytest.raises(so.InputError, match="create it"):
        ws.plot_3d(tmp_path / "missing" / "cloud.png")


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize("n", [0, -5, 1.5, True, "100", None])
def test_bad_sample_counts_raise_input_error(robots, n):
    """n must be an integer >= MIN_SAMPLES."""
    with pytest.raises(so.InputError, match="integer >= 100"):
        workspace(robots["zavar2024"], n=n)


def test_bad_arguments_raise_input_error(robots):
    """A non-robot, a bad grid cell or footprint are refused; a tiny cell is refused early."""
    robot = robots["zavar2024"]
    with pytest.raises(so.InputError, match="scara_opt.Robot"):
        workspace("zavar2024")
    for grid in (0.0, -0.01, math.nan, math.inf, "1 cm"):
        with pytest.raises(so.InputError, match="grid"):
            workspace(robot, n=100, grid=grid)
    with pytest.raises(so.InputError, match="footprint"):
        workspace(robot, n=100, footprint="base")
    with pytest.raises(so.InputError, match="too small"):
        workspace(robot, n=100, grid=1e-7)
    for bad in ({"shape": "circle", "center": [0, 0], "radius": "big"},
                {"shape": "polygon", "vertices": [[0, 0], [1, np.nan], [1, 1]]},
                {"shape": "square"}):
        with pytest.raises(so.InputError, match="footprint"):
            Footprint(**bad)
    stranger = Footprint("circle", center=[0.0, 0.0], radius=0.01, links_from="elbow")
    with pytest.raises(so.InputError, match="'elbow' is not a joint"):
        workspace(robot, n=100, footprint=stranger)
    everything = Footprint("circle", center=[0.0, 0.0], radius=10.0)
    with pytest.raises(so.InputError, match="blocks all"):
        workspace(robot, n=100, footprint=everything)


@pytest.mark.parametrize("points, match", [
    ([0.1, 0.2, 0.3], "shape"),
    (np.zeros((4, 2)), "shape"),
    (np.zeros((2, 3, 1)), "shape"),
    ([[0.1, np.nan, 0.0], [0.0, 0.0, 0.0], [np.inf, 0.0, 0.0]], r"rows \[0, 2\]"),
    ([["a", "b", "c"]], "numeric"),
])
def test_bad_points_raise_input_error(zavar_ws, points, match):
    """contains() takes a finite (m, 3) array only, and names the offending rows."""
    with pytest.raises(so.InputError, match=match):
        zavar_ws.contains(points)


def test_contains_of_no_points_is_empty(zavar_ws, robots):
    """An empty (0, 3) query gives an empty answer, by either route."""
    assert zavar_ws.contains(np.zeros((0, 3))).shape == (0,)
    assert workspace(robots["nguyen"], n=100).contains(np.zeros((0, 3))).shape == (0,)


def test_a_projection_without_area_has_zero_area():
    """A single vertical slide projects to a point: area 0, the grid still answers contains."""
    slide = so.Robot.from_dh(DHRobot("slide", (DHJoint("d", "prismatic", lower=0.0,
                                                       upper=0.1),)))
    ws = workspace(slide, n=1000)
    assert ws.xy_area == 0.0 and ws.contains_method == "grid"
    assert ws.contains([[0.0, 0.0, 0.05], [0.0, 0.0, 0.2], [0.1, 0.0, 0.05]]).tolist() == [
        True, False, False]


def test_a_robot_without_movable_joints_cannot_be_loaded():
    """No Workspace can be asked of a robot with no movable joint: loading it already fails.

    The DH table is refused, and so is a URDF of fixed joints only (URDFError), so
    workspace() never sees such a robot.
    """
    with pytest.raises(so.URDFError, match="no movable joint"):
        DHRobot("rigid", (DHJoint("tip", "fixed", a=0.1),))
    urdf = ('<robot name="rigid"><link name="a"/><link name="b"/>'
            '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>')
    with pytest.raises(so.URDFError, match="no movable joint"):
        so.Robot(urdf)


# ---------------------------------------------------------------------- sizes and uncertainty
def test_the_area_uncertainty_holds_the_exact_area_and_shrinks_with_n():
    """xy_area ± xy_area_uncertainty holds the planar 2R arm's exact area: 20 seeds per n.

    The half-width (half the edge cells' area) shrinks as n grows and shows in the repr.
    The worst case uses 0.59 of it (n = 100, seed 13).
    Mutation: area_uncertainty is a quarter of the edge cells' area instead of half -> fails.
    """
    exact = planar_2r_area(L, 2 * SHOULDER, ELBOW)
    robot = planar_2r()
    widths = []
    for n in (100, 1000, 20_000):
        for seed in range(20):
            ws = workspace(robot, n=n, seed=seed)
            assert abs(ws.xy_area - exact) <= ws.xy_area_uncertainty
        widths.append(ws.xy_area_uncertainty)
    assert widths[0] > widths[1] > widths[2] > 0
    assert f"± {widths[2]:.2g} m²" in repr(ws)


@pytest.mark.parametrize("n", [2, 10, 99])
def test_fewer_samples_than_the_minimum_are_refused(robots, n):
    """n = 2 gave an area with no word of its uncertainty; below MIN_SAMPLES it is refused.

    Mutation: MIN_SAMPLES = 1 -> fails.
    """
    with pytest.raises(so.InputError, match=r"integer >= 100.*xy_area_uncertainty"):
        workspace(robots["zavar2024"], n=n)


def test_a_flat_workspace_has_no_uncertainty():
    """A projection without area has area 0 ± 0."""
    slide = so.Robot.from_dh(DHRobot("slide", (DHJoint("d", "prismatic", lower=0.0,
                                                       upper=0.1),)))
    assert workspace(slide, n=100).xy_area_uncertainty == 0.0


@pytest.mark.parametrize("n, match", [(10**12, r"about 473 TiB .*lower n"),
                                      (10**30, r"n=1e\+30\) would need about 5.2e\+32 B")])
def test_huge_sample_counts_are_refused_with_the_memory_estimate(robots, n, match):
    """n = 10**12 raised MemoryError, n = 10**30 numpy's "Maximum allowed dimension exceeded".

    Mutation: workspace without check_memory -> fails.
    """
    with pytest.raises(so.InputError, match=match + r".*scara_opt.checks.MAX_BYTES"):
        workspace(robots["zavar2024"], n=n)


def test_the_memory_limit_can_be_raised_on_purpose(robots, monkeypatch):
    """Past MAX_BYTES the call is refused; raising MAX_BYTES lets the same call run."""
    from scara_opt import checks

    monkeypatch.setattr(checks, "MAX_BYTES", 100_000)
    with pytest.raises(so.InputError, match="more than the 97.7 KiB allowed"):
        workspace(robots["zavar2024"], n=1000)
    monkeypatch.setattr(checks, "MAX_BYTES", 10**6)
    assert workspace(robots["zavar2024"], n=1000).n_samples == 1000


def test_a_memory_error_while_sampling_becomes_advice(robots, monkeypatch):
    """A MemoryError below the limit (a machine with less memory) is an InputError.

    Mutation: the sampling outside memory_guard -> fails (MemoryError escapes).
    """
    def exhausted(self, Q):
        raise MemoryError

    monkeypatch.setattr(so.Robot, "positions", exhausted)
    with pytest.raises(so.InputError, match=r"ran out of memory \(estimated .*\); lower n"):
        workspace(robots["zavar2024"], n=1000, footprint=False)


@pytest.mark.parametrize("grid", [1e308, 10.0])
def test_a_grid_cell_larger_than_the_workspace_is_refused(robots, grid):
    """grid = 1e308 raised OverflowError (cell**2); any cell wider than the region is refused.

    Mutation: the check removed -> fails.
    """
    with pytest.raises(so.InputError, match="larger than the workspace"):
        workspace(robots["zavar2024"], n=100, grid=grid)


FAR = [5000, 5000]  # [mm]: a zone no link reaches, so an accepted table would just work


@pytest.mark.parametrize("table, match", [
    ({"shape": "circle", "center": FAR, "radius": True}, "radius must be numeric"),
    ({"shape": "circle", "center": FAR, "radius": "12"}, "radius must be numeric"),
    ({"shape": "circle", "center": [True, False], "radius": 1}, "center must be numeric"),
    ({"shape": "circle", "center": [1, "a"], "radius": 1}, "center must be numeric"),
    ({"shape": "circle", "center": FAR, "radius": 1, "vertices": [FAR, FAR]}, "not vertices"),
    ({"shape": "polygon", "vertices": [[5000, 5000], [5001, 5000], [5001, 5001]],
      "radius": 5}, "not center"),
    ({"shape": "circle", "center": FAR, "radius": 1, "links_from": 3}, "links_from must be"),
    ({"shape": 5}, r"5 \(int\)"),
])
def test_footprint_tables_take_numbers_and_only_their_shapes_keys(robots, table, match):
    """[footprint] numbers are numbers (radius = true was 1, "12" was 12); no stray keys.

    A circle with vertices, or a polygon with a radius, silently ignored one of them.
    Mutation: from_robot reads the numbers with float() / np.asarray as before -> fails.
    """
    robot = robots["peng2025"].with_limits()
    robot.metadata = {**robots["peng2025"].metadata, "footprint": table}
    with pytest.raises(so.URDFError, match=match):
        workspace(robot, n=100)
