"""scara_opt.view: one self-contained HTML file, checked in a real browser (headless Chromium)."""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest
import umsgpack

import scara_opt as so
from scara_opt import view
from scara_opt.view.geometry import visual_model
from tests.conftest import DATA, ROOT

#: appended to a copy of the page: after load, render the frame and read its WebGL pixels
#: back, once whole and once per layer (the floor grid, the robot, the tool path, the
#: obstacles: each alone on a transparent background, so its pixels are the non-zero
#: alpha), read the control bar and the labels from the DOM, click "least clearance" and
#: read the tip's position, click play and read the time a second later and at the end; all
#: written into <pre id="probe"> for --dump-dom
PROBE = """<script>
window.addEventListener("load", function () { setTimeout(function () {
  var out = {}, q = function (id) { return document.getElementById(id); };
  var done = function () {
    var pre = document.createElement("pre");
    pre.id = "probe";
    pre.textContent = JSON.stringify(out);
    document.body.appendChild(pre);
  };
  try {
    var THREE = MeshCat.THREE, r = viewer.renderer, gl = r.getContext();
    var W = gl.drawingBufferWidth, H = gl.drawingBufferHeight, px = new Uint8Array(W * H * 4);
    out.size = [W, H];
    r.render(viewer.scene, viewer.camera);
    gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
    var colours = new Set();
    for (var i = 0; i < px.length; i += 4 * 97) colours.add(px[i] + "," + px[i+1] + "," + px[i+2]);
    out.colours = colours.size;
    var acts = viewer.animator.actions;
    out.frames = acts.map(function (a) { return a._clip.tracks[0].times.length; });
    out.times = acts.length ? Array.from(acts[0]._clip.tracks[0].times) : [];
    out.duration = viewer.animator.duration;
    var leaves = [];
    viewer.scene.traverse(function (o) { if (o.isMesh || o.isLine || o.isPoints) leaves.push(o); });
    var kinds = leaves.map(function (o) {
      var p = []; for (var x = o; x; x = x.parent) p.unshift(x.name); p = p.join("/") + "/";
      if (p.indexOf("/floor_grid/") >= 0 || p.indexOf("Scene/Grid/") === 0) return "grid";
      if (p.indexOf("/tool_path/") >= 0) return "path";
      var m = p.match(/\\/visuals\\/obstacle_([^\\/]+)\\//);
      if (m) return "obstacle " + m[1];
      if (p.indexOf("/visuals/tip/") >= 0) return "robot tip";
      return p.indexOf("/visuals/") >= 0 ? "robot" : "other";
    });
    var shown = leaves.map(function (o) { return o.visible; }), bg = viewer.scene.background;
    viewer.scene.background = null;
    r.setClearColor(0x000000, 0);
    var layer = function (want) {
      leaves.forEach(function (o, i) { o.visible = shown[i] && want(kinds[i]); });
      r.render(viewer.scene, viewer.camera);
      gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
      var n = 0, rows = 0, b = [W, H, -1, -1], per = new Array(H).fill(0);
      for (var y = 0; y < H; y++) for (var x = 0; x < W; x++) {
        if (px[4 * (y * W + x) + 3] === 0) continue;
        var row = H - 1 - y;  // counted from the top, as on the screen
        n++; rows += row; per[row]++;
        b[0] = Math.min(b[0], x); b[1] = Math.min(b[1], row);
        b[2] = Math.max(b[2], x); b[3] = Math.max(b[3], row);
      }
      return {n: n, box: b, mean_row: n ? rows / n : null, per_row: per};
    };
    var robot = function (k) { return k.indexOf("robot") === 0; };
    var obstacle = function (k) { return k.indexOf("obstacle ") === 0; };
    out.layers = {grid: layer(function (k) { return k === "grid"; }), robot: layer(robot),
                  path: layer(function (k) { return k === "path"; }), obstacles: layer(obstacle),
                  scene: layer(function (k) { return robot(k) || obstacle(k) || k === "path"; })};
    out.obstacle = {};
    kinds.filter(obstacle).forEach(function (k) {
      out.obstacle[k.slice(9)] = layer(function (j) { return j === k; });
    });
    leaves.forEach(function (o, i) { o.visible = shown[i]; });
    viewer.scene.background = bg;
    viewer.set_dirty();
    var box = function (e) {
      var b = e.getBoundingClientRect();
      return [b.left, b.top, b.right, b.bottom];
    };
    var onTop = function (e) {  // drawn and not covered: what a click at its centre reaches
      var b = e.getBoundingClientRect();
      if (!(b.width > 0 && b.height > 0)) return false;
      var t = document.elementFromPoint((b.left + b.right) / 2, (b.top + b.bottom) / 2);
      return !!t && (t === e || e.contains(t));
    };
    var ui = {};
    ["so-title", "so-bar", "so-play", "so-time", "so-clock", "so-least-go", "so-least",
     "so-least-note"].forEach(
      function (id) {
        var e = q(id);
        ui[id] = e && {box: box(e), top: onTop(e), text: e.textContent,
                       display: getComputedStyle(e).display};
      });
    ui.moves = Array.from(document.querySelectorAll(".so-move")).map(function (e) {
      return {box: box(e), top: onTop(e), start: +e.dataset.start, duration: +e.dataset.duration,
              lines: Array.from(e.children).map(function (c) { return c.textContent; })};
    });
    ui.labels = Array.from(document.querySelectorAll(".so-label")).map(function (e) {
      return {name: e.dataset.name, text: e.textContent, box: box(e),
              at: [parseFloat(e.style.left), parseFloat(e.style.top)],
              display: getComputedStyle(e).display};
    });
    out.ui = ui;
    var tip = leaves[kinds.indexOf("robot tip")];
    var tipAt = function () {
      var v = new THREE.Vector3(); tip.getWorldPosition(v);
      return viewer.scene.worldToLocal(v).toArray();
    };
    out.tip0 = tipAt();
    if (q("so-least-go")) {
      q("so-least-go").click();
      out.least = {tip: tipAt(), slider: +q("so-time").value, clock: q("so-clock").textContent};
    }
    if (q("so-play")) {
      q("so-play").click();
      var state = function () {
        return {slider: +q("so-time").value, playing: viewer.animator.playing,
                button: q("so-play").textContent, tip: tipAt()};
      };
      return setTimeout(function () {
        out.play = state();
        setTimeout(function () { out.end = state(); done(); }, 2500);
      }, 1000);
    }
  } catch (e) { out.error = String(e) + "\\n" + e.stack; }
  done();
}, 500); });
</script>"""

#: put first in the page's head: animation frames from timers, which headless Chromium's
#: virtual time runs in order (its own frames come or not, run to run)
FRAMES = """<script>
window.requestAnimationFrame = function (f) {
  return setTimeout(function () { f(performance.now()); }, 16);
};
</script>"""

#: the window of every browser test [px]
WINDOW = (1200, 900)


def _chromium() -> str:
    """The Chromium binary; in CI (.ci/run installs Debian's chromium) its absence fails."""
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is not installed: .ci/run installs it (apt-get install chromium)")
        pytest.skip("chromium is not installed here (CI installs it: apt-get install chromium)")
    return exe


def _probe(folder, page: str) -> dict:
    """What :data:`PROBE` reads of ``page`` in headless Chromium, in a :data:`WINDOW` window."""
    path = folder / "probe.html"
    page = page.replace("<head>", "<head>" + FRAMES, 1).replace("</body>", PROBE + "</body>")
    path.write_text(page, encoding="utf-8")
    out = subprocess.run(
        [_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
         "--use-angle=swiftshader", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         f"--user-data-dir={folder / 'profile'}", f"--window-size={WINDOW[0]},{WINDOW[1]}",
         "--virtual-time-budget=5000", "--dump-dom", path.as_uri()],
        capture_output=True, text=True, timeout=180)
    m = re.search(r'<pre id="probe">(.*?)</pre>', out.stdout, re.S)
    assert m, f"the page did not run its probe: {out.stderr[-2000:]}"
    result = json.loads(html.unescape(m.group(1)))
    assert "error" not in result, result["error"]
    return result


CELL = ROOT / "examples" / "scara_cell.toml"


def _cell_program(robot, cell):
    """examples/scara_cell_planning.py's pick-and-place program (5 moves), planned in ``cell``."""
    pick, place, up = [0.32, -0.05, -0.09], [0.03, 0.30, -0.075], np.array([0, 0, 0.02])
    checker = so.CollisionChecker(robot, cell)
    a = so.ik_all(robot, so.Target(np.add(pick, up)))[0].q
    b = [s.q for s in so.ik_all(robot, so.Target(np.add(place, up)), q0=a)
         if not checker.collides(s.q)][0]
    program = [so.LIN(so.Target(np.add(pick, up))), so.PTP(b),
               so.LIN(so.Target(place), speed=0.1), so.LIN(so.Target(np.add(place, up))),
               so.PTP(a)]
    start = so.ik_all(robot, so.Target(pick), q0=a)[0].q
    return so.plan(robot, program, start=start, cell=cell, margin=0.002, seed=0)


@pytest.fixture(scope="module")
def cell_program():
    """zavar2024, the scara cell of the docs (column, rack, tray, table) and its program."""
    robot = so.load_robot("zavar2024")
    cell = so.load_cell(CELL)
    return robot, cell, _cell_program(robot, cell)


@pytest.fixture(scope="module")
def pages(tmp_path_factory, cell_program):
    """What headless Chromium shows of three pages: ``plain`` (a move, no cell), ``cell``
    (the program in the scara cell) and ``open`` (the same without its table)."""
    robot, cell, traj = cell_program
    plain = so.time_parameterize([[0, 0, 0, 0], [1.0, -1.2, 0.04, 0.5]], robot)
    no_table = so.Cell([ob for ob in cell.obstacles if ob.name != "table"], name="no table")
    out = {}
    for name, motion, kw in (("plain", plain, {}), ("cell", traj, {}),
                             ("open", traj, {"cell": no_table})):
        folder = tmp_path_factory.mktemp(name)
        page = view.write_html(robot, motion, folder / "page.html", **kw).read_text()
        out[name] = (motion, page, _probe(folder, page))
    return out


def _free(out) -> tuple[float, float]:
    """The rows of the frame [px] left free by the heading above and the control bar below."""
    ui = out["ui"]
    return (ui["so-title"]["box"][3] if ui["so-title"] else 0.0,
            ui["so-bar"]["box"][1] if ui["so-bar"] else float(out["size"][1]))


def test_the_page_renders_and_animates_every_frame_in_chromium(pages):
    """Headless Chromium loads the file from disk, WebGL draws a non-blank canvas, and every
    animated node has one keyframe per trajectory sample (30 fps, both ends), the last at
    the trajectory's duration.

    Mutation caught: html() animating every other configuration (``fr.q[::2]``).
    """
    traj, page, out = pages["plain"]
    n = len(traj.times(1 / 30))
    assert not re.search(r"<(script|link|img)[^>]*(src|href)=", page)  # nothing fetched
    assert out["colours"] > 20  # background gradient, grid, robot: not a blank canvas
    assert out["frames"] and set(out["frames"]) == {n}
    assert out["duration"] == pytest.approx(traj.duration, rel=1e-6)


@pytest.mark.parametrize("name", ["plain", "cell", "open"])
def test_the_floor_grid_lies_below_the_robot_in_the_picture(pages, name):
    """On the rendered frame (the grid and the robot each drawn alone, read back from WebGL),
    at least three quarters of the grid's pixels lie below the robot's topmost pixel, and the
    grid reaches at least as low as the robot's lowest: the floor is under the robot, seen
    from above.

    Mutations caught: meshcat's own grid and camera (``_draw_floor`` not called, ``fit()``
    not run: the 20 m grid at z = 0 is a band above the robot, none of its pixels below the
    robot's top) -> fails; the grid at the top of the framed scene (``floor =
    allpts[:, 2].max()``) -> fails.
    """
    out = pages[name][2]
    grid, robot = out["layers"]["grid"], out["layers"]["robot"]
    assert grid["n"] > 500 and robot["n"] > 500
    top = robot["box"][1]
    assert sum(grid["per_row"][top:]) >= 0.75 * grid["n"]
    assert grid["box"][3] >= robot["box"][3]


def _area(box, width: float, rows: tuple[float, float]) -> float:
    """The share of the frame left free (``rows``: top, bottom [px]) a pixel box covers."""
    x0, y0, x1, y1 = box
    return (x1 - x0 + 1) * (min(y1, rows[1]) - max(y0, rows[0]) + 1) / (width * (rows[1] - rows[0]))


@pytest.mark.parametrize("name", ["plain", "open"])
def test_the_scene_fills_most_of_the_frame(pages, name):
    """The camera frames the robot's reach and the cell: on the rendered frame (each layer
    drawn alone, read back from WebGL), the floor grid under them covers more than half of the
    frame left free by the heading and the control bar; in a cell, the robot, the tool path
    and the obstacles alone have a bounding box covering more than half of it too.

    ``plain``: one move without a cell; ``open``: the scara cell's program without its table
    (with the table, the table alone would fill the frame even in a bad view).

    Mutations caught: ``fit()`` not run (meshcat's default camera) -> fails; the camera backed
    off twice as far (``cam.position ... -2 * D``) -> fails.
    """
    out = pages[name][2]
    width, rows = out["size"][0], _free(out)
    assert _area(out["layers"]["grid"]["box"], width, rows) > 0.5
    if name == "open":
        assert _area(out["layers"]["scene"]["box"], width, rows) > 0.5


def test_each_obstacle_is_labelled_where_it_is_drawn(pages, cell_program):
    """One label per obstacle, with its name, shown, inside the frame, its pointer on that
    obstacle's own pixels (the obstacle drawn alone, 3 px of slack).

    Mutations caught: no labels (the ``V.labels.forEach`` building them removed) -> fails;
    labels not placed after each render (``place()`` not called: all at the corner) -> fails.
    """
    _, cell, _ = cell_program
    out = pages["cell"][2]
    labels = {lab["name"]: lab for lab in out["ui"]["labels"]}
    assert sorted(labels) == sorted(ob.name for ob in cell.obstacles)
    W, H = out["size"]
    for name, lab in labels.items():
        assert lab["text"] == name and lab["display"] != "none"
        left, top, right, bottom = lab["box"]
        assert 0 <= left and right <= W and 0 <= top and bottom <= H, lab
        x0, y0, x1, y1 = out["obstacle"][name]["box"]
        x, y = lab["at"]
        assert x0 - 3 <= x <= x1 + 3 and y0 - 3 <= y <= y1 + 3, (name, lab["at"], (x0, y0, x1, y1))


def _x(out, t: float) -> float:
    """Where the time slider's thumb centre is at ``t`` [s] (its ends inset by 7 px)."""
    left, _, right, _ = out["ui"]["so-time"]["box"]
    return left + 7 + (right - left - 14) * t / out["duration"]


def test_play_time_moves_and_least_clearance_are_on_the_page_without_a_menu(
        pages, cell_program):
    """The control bar shows play, the time slider, the clock and the least-clearance button,
    each on top (a click at its centre reaches it) without opening a menu; one block per move
    on the slider, from its start to its end, labelled with its number, kind and duration;
    the least-clearance mark where the slider's thumb is at that instant; play runs the
    clock from there, a second in a second, and stops at the end with the robot there.

    Mutations caught: no control bar (``if (T > 0)`` -> ``if (false)``: play and time only
    under "Open Controls") -> fails; each block drawn from the move's end (``left`` from
    ``m.start + m.duration``) -> fails; the mark at half the time -> fails; the button not
    set back to play at the end (``tick`` not comparing ``an.playing``) -> fails.
    """
    robot = cell_program[0]
    _, _, traj = cell_program
    out = pages["cell"][2]
    ui = out["ui"]
    for name in ("so-play", "so-time", "so-clock", "so-least-go"):
        assert ui[name] and ui[name]["top"], name
    assert ui["so-bar"]["box"][3] <= out["size"][1]
    t = traj.waypoint_times
    assert len(ui["moves"]) == len(traj.moves) == 5
    for k, (block, move) in enumerate(zip(ui["moves"], traj.moves, strict=True)):
        assert block["top"]
        assert block["start"] == pytest.approx(t[k]) and block["duration"] == pytest.approx(
            t[k + 1] - t[k])
        assert block["lines"] == [f"{k + 1} {move.kind}", f"{t[k + 1] - t[k]:.2f} s"]
        assert block["box"][0] == pytest.approx(_x(out, t[k]), abs=1.0)
        assert block["box"][2] == pytest.approx(_x(out, t[k + 1]), abs=1.0)
    least = view.timeline.least_clearance(traj.checker, traj)
    left, _, right, _ = ui["so-least"]["box"]
    assert (left + right) / 2 == pytest.approx(_x(out, least.time), abs=1.0)
    assert ui["so-least-go"]["text"] == (
        f"least clearance {least.distance * 1e3:.2f} mm ({least.bodies[0]}\u2013"
        f"{least.bodies[1]}) at {least.time:.3f} s")
    assert out["play"]["button"].endswith("pause") and out["play"]["playing"]
    assert out["play"]["slider"] - least.time == pytest.approx(1.0, abs=0.1)  # from the mark
    assert out["end"]["button"].endswith("play") and not out["end"]["playing"]
    assert out["end"]["slider"] == pytest.approx(traj.duration)
    end = robot.positions(traj.evaluate(np.array([traj.duration])))[0]
    np.testing.assert_allclose(out["end"]["tip"], end, atol=1e-5)


def test_going_to_least_clearance_shows_the_pose_there(pages, cell_program):
    """The least-clearance button moves the slider, the clock and the robot to that instant:
    the tip drawn is at the tip's FK there; each move's start and that instant are keyframes
    (shown exactly, not interpolated).

    Mutations caught: the button seeking to 0 -> fails; ``frames()`` ignoring ``at`` (the
    instants only between keyframes) -> fails.
    """
    robot, _, traj = cell_program
    out = pages["cell"][2]
    least = view.timeline.least_clearance(traj.checker, traj)
    assert out["least"]["slider"] == pytest.approx(least.time, abs=1e-9)
    assert out["least"]["clock"].startswith(f"{least.time:.3f} / ")
    tip = robot.positions(traj.evaluate(np.array([least.time])))[0]
    np.testing.assert_allclose(out["least"]["tip"], tip, atol=1e-5)
    assert np.abs(np.subtract(out["tip0"], tip)).max() > 0.05  # it moved there
    keys = np.array(out["times"])
    for when in [*traj.waypoint_times[:-1], least.time]:
        assert np.abs(keys - when).min() < 1e-6, when


def test_least_clearance_is_the_closest_pair_along_the_trajectory(cell_program):
    """The instant of least clearance is where the trajectory comes closest to the cell: the
    distance there is the pair's at that instant, no sample of a 1 ms grid comes more than
    0.1 mm closer, and the proven clearance bound lies below it.

    Mutation caught: the timeline taking the search's proven bound for the distance
    (``found.lower``) -> not the distance at that instant; fails.
    """
    _, _, traj = cell_program
    checker = traj.checker
    least = view.timeline.least_clearance(checker, traj)
    q = traj.evaluate(np.array([least.time]))[0]
    assert checker.clearance(q).distance == pytest.approx(least.distance, abs=1e-12)
    assert least.bodies == checker.clearance(q).bodies
    fine = checker.clearance_many(traj.evaluate(traj.times(0.001))).min()
    assert least.distance - 1e-4 <= fine + 1e-12
    assert traj.check_collisions().clearance <= least.distance


def _view_data(page: str) -> dict:
    """The ``SCARA_VIEW`` JSON a page carries."""
    return json.loads(re.search(r"var SCARA_VIEW = (\{.*?\});\n", page).group(1))


def test_a_cell_without_collision_geometry_says_why_there_is_no_least_clearance():
    """A robot without collision geometry viewed in a cell: the page is written, its
    obstacles labelled, and the bar says why there is no least clearance (never silently).

    Mutation caught: the ``CellError`` not caught in ``timeline.marks`` (html() raises) -> fails.
    """
    robot = so.Robot.from_urdf(DATA / "arm6.urdf")
    q1 = np.clip(np.full(robot.nq, 0.6), robot.lower, robot.upper)
    traj = so.time_parameterize([np.zeros(robot.nq), q1], robot, vmax=1.0, amax=2.0)
    shelf = so.Cell([so.Box("shelf", (0.3, 0.6, 0.02), xyz=(0.5, 0, 0.3))])
    data = _view_data(view.html(robot, traj, cell=shelf))
    assert data["least"] is None and data["least_note"].startswith("no least clearance: ")
    assert "collision geometry" in data["least_note"]
    assert [lab["name"] for lab in data["labels"]] == ["shelf"]


def test_the_grid_lies_on_the_table_or_under_the_cell(cell_program):
    """In the scara cell the grid lies on the table's top (the widest obstacle under the
    base); without the table, under everything framed (the column's foot).

    Mutation caught: ``_table`` ignored (the grid under the table, at its bottom) -> fails.
    """
    robot, cell, traj = cell_program
    Q = view.frames(robot, traj).q
    lay = view.framing.layout(robot, Q, cell)
    table = cell["table"]
    assert lay.table == "table"
    assert lay.floor == pytest.approx(table.xyz[2] + table.size[2] / 2, abs=1e-3)
    no_table = so.Cell([ob for ob in cell.obstacles if ob.name != "table"])
    lay = view.framing.layout(robot, Q, no_table)
    column = cell["column"]
    assert lay.table is None
    assert lay.floor == pytest.approx(column.xyz[2] - column.length / 2, abs=1e-9)
    grid = lay.grid_segments()
    assert np.all(grid[2] == lay.floor)


def test_a_floor_wider_than_the_reach_is_framed_only_within_it():
    """A 6 m floor slab is framed only within the robot's reach (cube grown by 10 %), and an
    obstacle 5 m away is neither framed nor labelled.

    Mutation caught: the boxes not clipped to the reach cube -> fails.
    """
    robot = so.load_robot("zavar2024")
    cell = so.Cell([so.Box("floor", (6.0, 6.0, 0.02), xyz=(0, 0, -0.2)),
                    so.Sphere("far", 0.1, xyz=(5.0, 0, 0))])
    lay = view.framing.layout(robot, np.zeros((2, 4)), cell)
    assert [name for name, _ in lay.labels] == ["floor"]
    reach = 0.4  # two 200 mm links: the reach is at most 0.8 m across
    assert np.ptp(lay.points[:, :2], axis=0).max() <= 1.2 * 2 * reach + 3e-3


def test_frames_of_each_kind_of_motion():
    """A Trajectory is sampled at fps and at the instants asked, a JointPath and an array give
    one frame per row, one pose one frame; fps and the instants are checked.

    Mutation caught: ``frames()`` ignoring ``at`` -> fails.
    """
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize([[0, 0, 0, 0], [0.5, 0.5, 0.01, 0.5]], robot)
    fr = view.frames(robot, traj, fps=10)
    assert fr.count == len(traj.times(0.1)) and fr.t[-1] == traj.duration
    fr = view.frames(robot, traj, fps=10, at=[0.123, 0.2])
    assert fr.count == len(traj.times(0.1)) + 1 and 0.123 in fr.t  # 0.2 is on the grid
    np.testing.assert_allclose(fr.q[list(fr.t).index(0.123)], traj.evaluate([0.123])[0])
    with pytest.raises(so.InputError, match="at: instants"):
        view.frames(robot, traj, at=[traj.duration + 1])
    with pytest.raises(so.InputError, match="at: only a Trajectory"):
        view.frames(robot, np.zeros((3, 4)), at=[0.1])
    path = so.ik_path(robot, so.paths.zavar2024_circle(reachable=True)[:4])
    assert view.frames(robot, path).count == 4
    assert view.frames(robot, np.zeros((3, 4))).count == 3
    assert view.frames(robot, [0, 0, 0, 0]).count == 1
    with pytest.raises(so.InputError, match="fps"):
        view.frames(robot, traj, fps=0)
    with pytest.raises(so.ScaraOptError):
        view.frames(robot, [[0.0, 0.0, 0.0]])  # three values for four joints


def _scene(robot, motion, **kw):
    """{path: decoded set_object command} of the recorded scene (``kw``: html's options)."""
    from meshcat.servers.tree import walk

    from scara_opt.view.scene import recording_visualizer

    recorded = {}
    real = view.scene.recording_visualizer

    def spy():
        vis = recording_visualizer()
        recorded["vis"] = vis
        return vis

    view.scene.recording_visualizer = spy
    try:
        view.html(robot, motion, **kw)
    finally:
        view.scene.recording_visualizer = real
    objects = [umsgpack.unpackb(node.object) for node in walk(recorded["vis"].window.tree)
               if node.object is not None]
    return {o["path"]: o for o in objects}


def test_a_dh_robot_is_a_stick_figure_and_the_tool_path_is_drawn():
    """No <visual> in the URDF: cylinders and spheres, one sphere per joint and the tip; the
    tip's path is a line through every frame's tip position."""
    robot = so.load_robot("zavar2024")
    geom = visual_model(robot)
    kinds = [type(o.geometry).__name__ for o in geom.geometryObjects]
    assert kinds.count("Sphere") == robot.nq + 1 and "Cylinder" in kinds
    Q = np.linspace([0, 0, 0, 0], [1.0, -1.0, 0.04, 0.3], 7)
    objects = _scene(robot, Q)
    line = objects["/meshcat/tool_path"]["object"]
    array = line["geometries"][0]["data"]["attributes"]["position"]["array"]
    points = np.frombuffer(array.data, dtype=np.float32).reshape(-1, 3)  # a msgpack Ext
    np.testing.assert_allclose(points, robot.positions(Q), atol=1e-6)


def test_a_urdf_with_meshes_is_drawn_with_them(tmp_path):
    """A URDF whose links have mesh visuals: the page carries the STL meshes themselves.

    Mutation caught: visual_model() ignoring the URDF's visuals (stick figure for all).
    """
    stl = tmp_path / "box.stl"
    stl.write_text("solid box\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                   "   vertex 0.1 0 0\n   vertex 0 0.1 0\n  endloop\n endfacet\nendsolid box\n")
    urdf = (DATA / "arm6.urdf").read_text()
    visual = (f'<visual><geometry><mesh filename="{stl}" scale="1 1 1"/></geometry></visual>')
    urdf = re.sub(r'<link name="(\w+)"\s*/>', rf'<link name="\1">{visual}</link>', urdf, count=3)
    robot = so.Robot(urdf, "tool0")
    objects = _scene(robot, np.zeros((2, robot.nq)))
    meshes = [o for o in objects.values() if o["object"]["geometries"][0].get("format") == "stl"]
    assert len(meshes) >= 1


def test_reproduce_writes_one_animation_per_paper_and_says_so(tmp_path, monkeypatch):
    """``run_paper`` writes ``<paper>_animation.html`` (a meshcat page of the report's motion)
    and links it in the summary; without meshcat it writes none and the report's notes say
    how to get it (never silently).

    Mutations caught: ``_write_animation`` not called from ``run_paper`` (no file); the
    missing-module branch without its note; ``write_html`` outside the ``try`` (the
    base install's ``reproduce`` then crashed: found by ``.ci/run``).
    """
    import sys

    from scara_opt.reports import run_paper

    rep = run_paper("inverted5", tmp_path / "with")
    page = tmp_path / "with" / "inverted5_animation.html"
    assert rep.animation_file == page and page.stat().st_size > 100_000
    assert "new MeshCat.Viewer" in page.read_text()
    assert "[inverted5_animation.html](inverted5_animation.html)" in rep.to_markdown()

    # as in a base install: the viewer's meshcat scene cannot be imported
    monkeypatch.setitem(sys.modules, "scara_opt.view.scene", None)
    rep = run_paper("inverted5", tmp_path / "without")
    assert rep.animation_file is None
    assert not (tmp_path / "without" / "inverted5_animation.html").exists()
    assert any("scara-opt[view]" in note for note in rep.notes)


def test_a_motion_planned_in_a_cell_draws_its_obstacles(tmp_path):
    """A PTP planned around a post: the page has the post (a cylinder of its size), a box
    and a mesh given with cell=, and the tool path planned around them.

    Mutation caught: html() ignoring the trajectory's cell (no obstacle in the scene).
    """
    import trimesh

    robot = so.load_robot("zavar2024")
    post = so.Cell([so.Cylinder("post", 0.03, 0.4, xyz=(0.3, 0.15, 0.0))])
    traj = so.plan(robot, [so.PTP([1.2, 0.5, 0.0, 0.0])], start=[-0.5, 0.5, 0.0, 0.0],
                   cell=post)
    objects = _scene(robot, traj)
    drawn = [k for k in objects if "obstacle_post" in k]
    assert len(drawn) == 1
    assert "/meshcat/tool_path" in objects
    trimesh.creation.box((0.05, 0.05, 0.05)).export(tmp_path / "b.stl")
    cell = so.Cell([so.Box("block", (0.1, 0.1, 0.1), xyz=(0.3, 0, -0.2)),
                    so.Mesh("part", tmp_path / "b.stl", xyz=(0.2, 0.2, -0.2))])
    objects = _scene(robot, np.zeros((2, 4)), cell=cell)
    assert any("obstacle_block" in k for k in objects)
    part = [o for k, o in objects.items() if "obstacle_part" in k]
    assert part and part[0]["object"]["geometries"][0].get("format") == "stl"
    with pytest.raises(so.InputError, match="cell must be"):
        view.html(robot, np.zeros((2, 4)), cell="cell.toml")
