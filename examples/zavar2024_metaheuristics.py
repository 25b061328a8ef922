# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""zavar2024 metaheuristics: Table 2, Figs. 4, 5 and 7, against IPOPT and the closed form.

Needs: the base install only (``pip install scara-opt``).

Reproduces Zavar, Manouchehri & Safa (robots/zavar2024.toml [citation]), Sec. 6: the six
algorithms (CA, GWO, PSO, G-HA, FA, ACO) at populations 20-100 and 200 iterations, median over
10 seeds, side by side with the paper's costs (its squared error) and times; the paper's fixed
target and circle reported as unreachable (they are), and the studies rerun on reachable
variants. Prints Table 2 and the findings; saves Figs. 4, 5 and 7 into ``examples/out/``.
``--quick``: 3 seeds, 3 populations.
"""

from __future__ import annotations

import sys
from pathlib import Path

from scara_opt.reports.zavar2024 import run

OUT = Path(__file__).resolve().parent / "out"
COLUMNS = ["method", "population", "abs_err_x", "abs_err_y", "abs_err_z", "error", "cost",
           "paper_cost", "time_s", "within_tol", "paper_time_s", "speedup_vs_paper"]


def main(quick: bool = False) -> None:
    report = run(OUT, quick=quick)
    table = report.tables["table2"][COLUMNS]
    print(table.to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print()
    for f in report.findings:
        print(f"[{f.verdict}] {f.item}: {f.ours}")
    for note in report.notes:
        print(note)
    for path in report.figures:
        print(f"wrote {path}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv[1:])
