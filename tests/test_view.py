"""scara_opt.view: one self-contained HTML file, checked in a real browser (headless Chromium)."""

from __future__ import annotations

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
from tests.conftest import DATA

#: appended to a copy of the page: after load, render once, read the WebGL pixels back and
#: the animation's keyframe counts, and write them into <pre id="probe"> for --dump-dom
PROBE = """<script>
window.addEventListener("load", function () { setTimeout(function () {
  var out = {};
  try {
    var r = viewer.renderer, gl = r.getContext();
    r.render(viewer.scene, viewer.camera);
    var w = gl.drawingBufferWidth, h = gl.drawingBufferHeight, px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    var colours = new Set();
    for (var i = 0; i < px.length; i += 4 * 97) colours.add(px[i] + "," + px[i+1] + "," + px[i+2]);
    out.colours = colours.size;
    out.frames = viewer.animator.actions.map(
      function (a) { return a._clip.tracks[0].times.length; });
    out.duration = viewer.animator.duration;
  } catch (e) { out.error = String(e); }
  var pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
}, 500); });
</script>"""


def _chromium() -> str:
    """The Chromium binary; in CI (.ci/run installs Debian's chromium) its absence fails."""
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        if os.environ.get("CI"):
            pytest.fail("chromium is not installed: .ci/run installs it (apt-get install chromium)")
        pytest.skip("chromium is not installed here (CI installs it: apt-get install chromium)")
    return exe


def _probe(tmp_path, page: str) -> dict:
    path = tmp_path / "probe.html"
    path.write_text(page.replace("</body>", PROBE + "</body>"), encoding="utf-8")
    out = subprocess.run(
        [_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
         "--use-angle=swiftshader", "--window-size=800,600", "--virtual-time-budget=5000",
         "--dump-dom", path.as_uri()], capture_output=True, text=True, timeout=180)
    m = re.search(r'<pre id="probe">(.*?)</pre>', out.stdout)
    assert m, f"the page did not run its probe: {out.stderr[-2000:]}"
    return json.loads(m.group(1))


def test_the_page_renders_and_animates_every_frame_in_chromium(tmp_path):
    """Headless Chromium loads the file from disk, WebGL draws a non-blank canvas, and every
    animated node has one keyframe per trajectory sample (30 fps, both ends).

    Mutation caught: html() animating every other configuration (``fr.q[::2]``).
    """
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize([[0, 0, 0, 0], [1.0, -1.2, 0.04, 0.5]], robot)
    n = len(traj.times(1 / 30))
    path = view.write_html(robot, traj, tmp_path / "move.html")
    page = path.read_text()
    assert not re.search(r"<(script|link|img)[^>]*(src|href)=", page)  # nothing fetched
    out = _probe(tmp_path, page)
    assert "error" not in out, out
    assert out["colours"] > 20  # background gradient, grid, robot: not a blank canvas
    assert out["frames"] and set(out["frames"]) == {n}
    assert out["duration"] == pytest.approx((n - 1) / 30, rel=1e-6)


def test_frames_of_each_kind_of_motion():
    """A Trajectory is sampled at fps, a JointPath and an array give one frame per row, one
    pose one frame; fps is checked."""
    robot = so.load_robot("zavar2024")
    traj = so.time_parameterize([[0, 0, 0, 0], [0.5, 0.5, 0.01, 0.5]], robot)
    assert view.frames(robot, traj, fps=10).count == len(traj.times(0.1))
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
