# /// script
# requires-python = ">=3.11"
# dependencies = ["scara-opt"]
# ///
"""fang joint trajectories: Tables 2 and 3 by the quintic, then time-optimal and jerk-limited.

Needs: the base install only (``pip install scara-opt``).

Reproduces Fang & Li (robots/fang.toml [citation]), Sec. 4: the quintic of
Tables 2 and 3 against every printed row (36 samples at τ = k/35; degrees and mm), then the
same two moves timed within the robot's assumed limits (robots/fang.toml) by the shortest
quintic, TOPP-RA (time-optimal) and Ruckig (jerk-limited), and the paper's arccos closed form
where it fails (py < 0), and beyond the paper the Table 2 move under torque limits with a
payload of 0, 1 and 2 kg (estimated masses and torques, robots/fang.toml). Prints the tables;
saves ``examples/out/fang_table2_move.png`` and ``fang_table3_move.png`` (q, qd, qdd per joint
with the limit lines).
"""

from __future__ import annotations

from pathlib import Path

from scara_opt.reports.fang import run

OUT = Path(__file__).resolve().parent / "out"


def main() -> None:
    report = run(OUT)
    check = report.tables["tables2_3_check"]
    print(check[check["row"].isin([1, 2, 10, 11])].round(4).to_string(index=False))
    print()
    print(report.tables["timing"].round(4).to_string(index=False))
    print()
    print(report.tables["payload_timing"].round(4).to_string(index=False))
    print()
    for f in report.findings:
        print(f"[{f.verdict}] {f.item}: {f.ours}")
    for path in report.figures:
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
