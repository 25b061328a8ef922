# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""nguyen cutting path: IK of the 5-DoF rail SCARA along a closed contour, SFLA and IPOPT.

Needs: the base install only (``pip install scara-opt``).

Reproduces the path study of Nguyen (robots/nguyen.toml [citation]), Sec. 4-5, on a
representative contour (the paper's is a figure only): the largest position and angle error
of SFLA (the paper's Table 2 settings) and of IPOPT side by side (Figs. 10-11), the joints
along the path (Figs. 12-13), postures (Figs. 14-15), and the IPOPT path timed by TOPP-RA.
Prints the table; saves PNGs into ``examples/out/``. ``--quick``: fewer points.
"""

from __future__ import annotations

import sys
from pathlib import Path

from scara_opt.reports.nguyen import run

OUT = Path(__file__).resolve().parent / "out"


def main(quick: bool = False) -> None:
    report = run(OUT, quick=quick)
    print(report.tables["cutting_path"].to_string(index=False))
    for note in report.notes:
        print(note)
    for path in report.figures:
        print(f"wrote {path}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv[1:])
