"""Report verdicts are computed from measurements: broken solvers never read "matched"."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import scara_opt as so
from scara_opt.ik import analytic
from scara_opt.ik import registry as ik_registry
from scara_opt.ik.base import default_q0
from scara_opt.ik.result import SolverOutput
from scara_opt.reports import PAPERS, Finding, run_paper
from scara_opt.reports import verdicts as rules
from scara_opt.trajectory import registry as timing_registry


def _broken(cls: type) -> type:
    """``cls`` whose search returns its start (q0, or the default start) unchanged."""

    class Broken(cls):  # type: ignore[misc, valid-type]
        def _solve(self, robot, target, q0, rng, tol):  # noqa: ANN001, ANN202
            return SolverOutput(q=default_q0(robot) if q0 is None else q0.copy())

    return Broken


@pytest.fixture
def broken_solvers(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every registered IK method returns q0, the closed form returns q0 as its only branch,
    and every timing method times the path backwards."""
    for name, factory in list(ik_registry._REGISTRY.items()):
        monkeypatch.setitem(ik_registry._REGISTRY, name, _broken(factory))
    monkeypatch.setattr(analytic, "solve_all", lambda robot, target, q_ref, fixed=None:
                        [q_ref.copy()])
    for name, entry in list(timing_registry._REGISTRY.items()):
        backwards = (lambda fn: lambda Q, *a, **k: fn(np.ascontiguousarray(Q[::-1]), *a,
                                                      **k))(entry.backend)
        monkeypatch.setitem(timing_registry._REGISTRY, name, replace(entry, backend=backwards))


@pytest.mark.parametrize("paper", PAPERS)
def test_no_matched_verdict_from_broken_solvers(broken_solvers, paper, tmp_path):
    """With every solver broken (IK returns q0, timing runs backwards), no finding that rests
    on IK or timing says "matched", and each such finding's verdict is one of the rules'.

    Mutations caught: any report verdict written as the constant "matched" (e.g. peng2025's
    two-branch row, inverted5's "every answer reaches it", fang's table rows); a reach rule
    that treats "both miss" as a match (zavar2024's GWO row); a best-method rule that ignores
    whether the best method reaches (zavar2024's conclusion with every method tied).
    """
    report = run_paper(paper, tmp_path, quick=True)
    measured = [f for f in report.findings if f.basis in ("ik", "timing")]
    assert measured, "the report has no finding that rests on a solver"
    matched = [f.item for f in measured if f.verdict == rules.MATCHED]
    assert not matched, matched


@pytest.mark.parametrize("paper, item", [("peng2025", "eq. 4.6"), ("inverted5", "Fig. 3")])
def test_no_matched_verdict_from_a_broken_fk(monkeypatch, paper, item, tmp_path):
    """A tip position off by 1 mm along z turns the FK checks into "differs".

    Mutation caught: an FK row whose verdict is the constant "matched".
    """
    position = so.Robot.position
    monkeypatch.setattr(so.Robot, "position", lambda self, q: position(self, q) + [0, 0, 1e-3])
    report = run_paper(paper, tmp_path, quick=True)
    rows = [f for f in report.findings if f.basis == "fk" and f.item.startswith(item)]
    assert rows and all(f.verdict == rules.DIFFERS for f in rows)


def test_working_solvers_match_where_the_paper_is_right(tmp_path):
    """With the real solvers the same reports do say "matched" where the paper holds.

    Guards the other way: a rule that never matches (a constant "differs") fails here.
    """
    for paper in ("peng2025", "inverted5", "fang"):
        report = run_paper(paper, tmp_path, quick=True)
        assert any(f.verdict == rules.MATCHED and f.basis in ("ik", "timing")
                   for f in report.findings), paper


def test_claim_of_reach_rule():
    """Solved -> matched; certified misses -> paper inconsistent; an uncertified miss -> differs.

    Mutation caught: "paper inconsistent" granted for any miss (a max_iter one included).
    """
    robot = so.load_robot("zavar2024")
    solved = so.solve_ik(robot, [-0.23, 0.20, -0.07])
    unreachable = so.solve_ik(robot, [-0.23, 0.20, -0.20])
    budget = so.solve_ik(robot, [-0.23, 0.20, -0.07], method="pso", population=4, iterations=1)
    assert (solved.status, unreachable.status, budget.status) == ("solved", "unreachable",
                                                                   "max_iter")
    assert rules.claim_of_reach([solved])[0] == rules.MATCHED
    assert rules.claim_of_reach([solved, unreachable])[0] == rules.INCONSISTENT
    assert rules.claim_of_reach([unreachable, budget])[0] == rules.DIFFERS


def test_reach_and_order_rules():
    """The numeric rules: both reach, both miss by as much, rankings, ratios; a difference
    says which side ours is on (issue 38: "80x faster" and "25x smaller error" both read
    "differs", as failures).

    Mutations caught: reach_claims' sides swapped (``BETTER if median_error < paper_error
    / 10`` -> ``>``) and ratio_within's (``(ratio < 1) == smaller_is_better`` -> ``!=``):
    each fails.
    """
    assert rules.reach_claims(True, 0.9, 1e-9, 1e-12)[0] == rules.MATCHED
    assert rules.reach_claims(True, 0.4, 1e-5, 1e-12)[0] == rules.WORSE  # we miss, it reaches
    assert rules.reach_claims(False, 0.9, 1e-9, 3e-3)[0] == rules.BETTER  # we reach, it misses
    assert rules.reach_claims(False, 0.0, 2e-3, 3e-3)[0] == rules.MATCHED
    assert rules.reach_claims(False, 0.0, 0.3, 3e-3)[0] == rules.WORSE  # a far worse miss
    assert rules.reach_claims(False, 0.0, 1e-4, 3e-3)[0] == rules.BETTER  # 30x smaller
    assert rules.same_order(["a", "b"], ["a", "b"], ranked=True)[0] == rules.MATCHED
    assert rules.same_order(["a", "b"], ["a", "b"], ranked=False)[0] == rules.DIFFERS
    assert rules.best_is("ca", "ca", 0.2)[0] == rules.DIFFERS
    assert rules.ratio_within(1.5, 1.0, 2.0)[0] == rules.MATCHED
    assert rules.ratio_within(0.01, 1.0, 2.0)[0] == rules.BETTER  # 100x faster
    assert rules.ratio_within(5.0, 1.0, 2.0)[0] == rules.WORSE
    assert rules.ratio_within(5.0, 1.0, 2.0, smaller_is_better=False)[0] == rules.BETTER
    assert rules.within(1.0, 1.0 + 2e-9, 1e-9)[0] == rules.DIFFERS


def test_a_finding_refuses_an_unknown_verdict():
    """Verdicts are a closed set: a typo is an error, not a new category."""
    with pytest.raises(ValueError, match="unknown verdict"):
        Finding("x", "y", "z", "matched!")


def test_papers_in_processes_write_what_a_serial_run_writes(tmp_path):
    """``reproduce(jobs=2)`` (a worker process per lane of papers) writes the files of a
    serial run, with the same numbers in every table but the time columns, and returns the
    reports in the order asked.

    Mutations: the reports returned in lane order (``for lane in lanes for name in lane``)
    -> order differs, fails; the quick flag not passed on (``"0"`` always) -> peng2025's
    quick tables differ, fails.
    """
    import pandas as pd

    from scara_opt.reports import reproduce

    names = ["inverted5", "peng2025"]
    serial = reproduce(names, tmp_path / "serial", quick=True, jobs=1)
    parallel = reproduce(names, tmp_path / "parallel", quick=True, jobs=2)
    assert [r.paper for r in parallel] == names == [r.paper for r in serial]
    files = sorted(p.name for p in (tmp_path / "serial").iterdir())
    assert files == sorted(p.name for p in (tmp_path / "parallel").iterdir())
    for name in (f for f in files if f.endswith(".csv")):
        a, b = (pd.read_csv(tmp_path / d / name) for d in ("serial", "parallel"))
        keep = [c for c in a.columns if not c.endswith("_s") and "speedup" not in c]
        pd.testing.assert_frame_equal(a[keep], b[keep])
    for a, b in zip(serial, parallel, strict=True):
        assert [(f.item, f.verdict) for f in a.findings] == [
            (f.item, f.verdict) for f in b.findings]


def test_a_failing_paper_worker_is_an_error_with_its_stderr(tmp_path):
    """A worker that fails (here: a paper name the worker refuses) raises RuntimeError
    carrying the end of its stderr, not a missing-file error later.

    Mutation: the return code not checked -> FileNotFoundError on the missing report, fails.
    """
    from scara_opt.reports import _in_processes

    with pytest.raises(RuntimeError, match="unknown paper 'nobody2020'"):
        _in_processes(["inverted5", "nobody2020"], tmp_path, True, 2)


def test_reproduce_jobs_must_be_a_whole_number():
    """jobs=0, 1.5 or True: InputError naming jobs (nothing run)."""
    from scara_opt.reports import reproduce

    for jobs in (0, 1.5, True):
        with pytest.raises(so.InputError, match="jobs"):
            reproduce(["inverted5"], "unused", jobs=jobs)
