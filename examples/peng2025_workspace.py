# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""peng2025 workspace: Monte Carlo reach with and without the base's exclusion zone.

Needs: the base install only (``pip install scara-opt``).

Reproduces the workspace study of Peng et al. (2025), Sec. 3
(robots/peng2025.toml [citation]):

* Fig. 3 — projection of the workspace on the XOY plane, joint limits only;
* Fig. 4 — the workspace by the Monte Carlo method, N = 60,000 samples (3D);
* Fig. 6 — the calibrated workspace: samples whose forearm passes through the base
  footprint (Fig. 5, the ``[footprint]`` table of robots/peng2025.toml) are dropped, which
  limits the elbow to about 120 degrees.

Prints the areas with and without the base zone and the PNG paths (in examples/out/).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import scara_opt as so
from scara_opt.workspace_analysis import workspace

ROBOT = "peng2025"
N = 60_000  # samples, as in the paper (Fig. 4)
SEED = 0
OUT = Path(__file__).resolve().parent / "out"


def main() -> None:
    OUT.mkdir(exist_ok=True)
    robot = so.load_robot(ROBOT)
    free = workspace(robot, n=N, seed=SEED, footprint=False)
    calibrated = workspace(robot, n=N, seed=SEED, footprint=True)

    paths = [
        free.plot_xy(OUT / "peng2025_fig3_workspace_xy.png",
                     title="peng2025 Fig. 3: workspace, XOY projection (joint limits only)"),
        free.plot_3d(OUT / "peng2025_fig4_monte_carlo_3d.png",
                     title=f"peng2025 Fig. 4: Monte Carlo workspace, N = {N}"),
        calibrated.plot_xy(OUT / "peng2025_fig6_calibrated_xy.png",
                           title="peng2025 Fig. 6: calibrated workspace (base footprint)"),
    ]

    elbow = np.degrees(np.abs(calibrated.q[:, robot.joint_names.index("theta2")]).max())
    mm = 1000.0
    print(f"{ROBOT}: {N} samples, seed {SEED}, grid cell {free.cell * mm:.1f} mm")
    print(f"  XY area without the base zone: {free.xy_area:.4f} m^2")
    print(f"  XY area with the base zone:    {calibrated.xy_area:.4f} m^2 "
          f"({calibrated.xy_area / free.xy_area:.1%}; {calibrated.n_dropped} samples dropped)")
    print(f"  largest elbow angle kept: {elbow:.2f} deg (joint limit 164 deg)")
    for label, ws in (("without", free), ("with", calibrated)):
        r0, r1 = ws.radial_range
        z0, z1 = ws.z_range
        print(f"  {label:>7} zone: radius from the shoulder axis {r0 * mm:.1f}-{r1 * mm:.1f} mm, "
              f"z {z0 * mm:.1f}-{z1 * mm:.1f} mm")
    for path in paths:
        print(f"  wrote {path}")


if __name__ == "__main__":
    main()
