"""Pictures of the robot: the stick figure through every joint origin, and path animations."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import scara_opt as so
from scara_opt.plots import animate, draw_robot


def test_draw_robot_goes_through_every_joint_origin_to_the_tip(robots, tmp_path):
    """The arm's polyline is the FK of each joint frame [mm], ending at the tool tip."""
    robot = robots["zavar2024"]
    q = np.array([0.3, -0.8, 0.02, 1.0])
    ax = draw_robot(robot, q, path=tmp_path / "pose.png")
    x, y, z = ax.lines[0].get_data_3d()
    arm = np.column_stack([x, y, z])
    np.testing.assert_allclose(arm, robot.joint_origins(q[None])[0] * 1000.0)
    np.testing.assert_allclose(arm[-1], robot.position(q) * 1000.0, atol=1e-9)
    assert (tmp_path / "pose.png").stat().st_size > 0


def test_draw_robot_into_a_subfigure_saves_the_whole_figure(robots, tmp_path):
    """An axes of a subfigure (which has no savefig) is saved through its root Figure.

    Mutation caught: saving ``ax.figure`` (the SubFigure: AttributeError 'savefig').
    """
    from matplotlib.figure import Figure

    robot = robots["zavar2024"]
    fig = Figure(figsize=(8, 4))
    left, right = fig.subfigures(1, 2)
    right.add_subplot().plot([0, 1], [0, 1])
    ax = draw_robot(robot, robot.lower, ax=left.add_subplot(projection="3d"),
                    path=tmp_path / "sub.png")
    assert ax.figure is left
    with Image.open(tmp_path / "sub.png") as img:  # both halves: wider than tall
        assert img.width > 1.5 * img.height


def test_animate_writes_one_frame_per_path_point(robots, tmp_path):
    """A GIF with one frame per configuration of the joint path (targets drawn too)."""
    robot = robots["zavar2024"]
    Q = np.linspace([0.0, -0.5, 0.0, 0.0], [1.0, 0.5, 0.03, 1.0], 5)
    targets = [so.Target(p) for p in robot.positions(Q)]
    out = animate(robot, Q, tmp_path / "path.gif", fps=5, targets=targets)
    with Image.open(out) as gif:
        assert gif.format == "GIF" and gif.n_frames == 5
    with pytest.raises(so.InputError, match="NaN"):
        animate(robot, Q, tmp_path / "bad.gif", targets=[[np.nan, 0.0, 0.0]])


@pytest.mark.parametrize("name, fps, match", [("path.png", 10, r"\*\.gif"),
                                               ("path.gif", 0, "fps")])
def test_animate_refuses_a_wrong_file_or_rate(robots, tmp_path, name, fps, match):
    """A file that is not .gif, or a non-positive frame rate, is refused before drawing."""
    with pytest.raises(so.InputError, match=match):
        animate(robots["zavar2024"], np.zeros((3, 4)), tmp_path / name, fps=fps)
    assert not (tmp_path / name).exists()


def test_path_figure_draws_reached_points_and_per_point_medians(robots, tmp_path):
    """zavar2024 Fig. 7 rerun: the xy panel's dots are where each run ended (FK of its q),
    not the targets, and each per-point line is the median over seeds of that column.

    Mutations caught: ``reached_x`` computed as target - error (dots mirrored off the arm's
    reach); the xy panel plotting the target columns instead of the reached ones; a line of
    the mean instead of the median.
    """
    from scara_opt.comparison import compare
    from scara_opt.plots import plot_path_runs

    robot = robots["zavar2024"]
    # the second target is 0.1 m beyond the arm's 0.4 m reach: its reached point differs
    targets = [so.Target([0.3, 0.0, -0.07]), so.Target([0.5, 0.0, -0.07])]
    table = compare(robot, targets, methods=["ipopt", "pso"], populations=[20], iterations=20,
                    seeds=[0, 1, 2], tol=1e-9, progress=False)
    far = so.solve_ik(robot, targets[1], method="ipopt")
    row = table[(table["method"] == "ipopt") & (table["target"] == 1)].iloc[0]
    reached = row[["reached_x", "reached_y", "reached_z"]].to_numpy(float)
    np.testing.assert_allclose(reached, robot.position(far.q), atol=1e-12)
    assert reached[0] < 0.41

    fig = plot_path_runs(table, ["abs_err_x", "time_s"], tmp_path / "circle.png", title="t")
    xy = fig.axes[0]
    dots = np.concatenate([np.column_stack(line.get_data()) for line in xy.lines[:-1]])
    np.testing.assert_allclose(np.sort(dots[:, 0]), np.sort(table["reached_x"]), atol=1e-15)
    err = fig.axes[1]
    pso = [line for line in err.lines if line.get_label() == "PSO"][0]
    runs = table[table["method"] == "pso"].groupby("target")["abs_err_x"].median()
    np.testing.assert_allclose(pso.get_ydata(), np.maximum(runs.to_numpy(), 1e-17))
    assert (tmp_path / "circle.png").stat().st_size > 0
