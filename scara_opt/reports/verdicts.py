"""The rules that turn a measured comparison with a paper into a verdict.

Every :class:`~scara_opt.reports.Finding` gets its verdict from one of these functions,
never from a constant: each takes what was measured and what the paper claims, and its
docstring (and the ``rule`` it returns) states the rule. The verdicts:

* ``matched``: the measurement agrees with the paper's claim by the stated rule;
* ``ours better``: it does not, and ours is the better side of the difference (faster, a
  smaller error, a target reached that the paper misses);
* ``ours worse``: it does not, and ours is the worse side (slower, a larger error, a
  target the paper reaches and we miss);
* ``differs``: it does not, and the difference has no better side (another ranking,
  another best method, a value off either way);
* ``paper inconsistent``: the paper claims a solution where a certificate proves there is
  none (an ``unreachable`` status, whose proof is in the result's message);
* ``figure only``: the paper gives a picture and no number (nothing is compared);
* ``beyond the paper``: a result the paper does not have (nothing is compared).
"""

from __future__ import annotations

from collections.abc import Sequence

from scara_opt.ik.result import IKResult, Status

MATCHED, DIFFERS = "matched", "differs"
BETTER, WORSE = "ours better", "ours worse"
INCONSISTENT, FIGURE_ONLY, BEYOND = "paper inconsistent", "figure only", "beyond the paper"
VERDICTS = (MATCHED, BETTER, WORSE, DIFFERS, INCONSISTENT, FIGURE_ONLY, BEYOND)


def within(ours: float, paper: float, tol: float) -> tuple[str, str]:
    """``matched`` when ``|ours - paper| <= tol``; returns (verdict, rule)."""
    return (MATCHED if abs(ours - paper) <= tol else DIFFERS), f"|ours - paper| <= {tol:g}"


def claim_of_reach(results: Sequence[IKResult]) -> tuple[str, str]:
    """The paper claims every target is reached: check each result (verdict, rule).

    ``matched`` when every result is ``solved``; ``paper inconsistent`` when every one that
    is not is ``unreachable`` (a certificate proves it) and at least one is; else
    ``differs`` (a solver missed a target that no proof puts out of reach).
    """
    rule = ("matched if every target is solved within tol; paper inconsistent if the misses "
            "are all certified unreachable")
    missed = [r for r in results if not r.success]
    if not missed:
        return MATCHED, rule
    if all(r.status == Status.UNREACHABLE for r in missed):
        return INCONSISTENT, rule
    return DIFFERS, rule


def reach_claims(paper_reaches: bool, share: float, median_error: float,
                 paper_error: float) -> tuple[str, str]:
    """Does a method reach 1e-6 as the paper says (or miss it, and by as much)?

    ``ours reaches`` means a majority of runs within 1e-6. ``matched`` when both reach, or
    when both miss and our median error is within a factor of 10 of the paper's. Else
    ``ours better`` (we reach where the paper misses, or both miss and our error is more
    than 10x smaller) or ``ours worse`` (the other way).
    """
    rule = ("matched if both reach 1e-6 (ours: > 50 % of runs), or both miss with our median "
            "error within 10x of the paper's; else ours better or worse")
    ours_reaches = share > 0.5
    if paper_reaches and ours_reaches:
        return MATCHED, rule
    if paper_reaches != ours_reaches:
        return (BETTER if ours_reaches else WORSE), rule
    if paper_error / 10 <= median_error <= paper_error * 10:
        return MATCHED, rule
    return (BETTER if median_error < paper_error / 10 else WORSE), rule


def same_order(ours: Sequence[str], paper: Sequence[str], *, ranked: bool) -> tuple[str, str]:
    """``matched`` when our ranking lists the methods in the paper's order.

    ``ranked`` is False when our measure does not separate the methods (all tied): then
    there is no ranking to compare, and the verdict is ``differs``.
    """
    rule = "matched if our ranking (share within 1e-6, then median error) equals the paper's"
    return (MATCHED if ranked and list(ours) == list(paper) else DIFFERS), rule


def best_is(best: str, claimed: str, best_share: float) -> tuple[str, str]:
    """``matched`` when our best method is the paper's and it reaches 1e-6 in most runs."""
    rule = "matched if the paper's best method ranks first here and reaches 1e-6 in > 50 % of runs"
    return (MATCHED if best == claimed and best_share > 0.5 else DIFFERS), rule


def ratio_within(ours: float, paper: float, factor: float,
                 smaller_is_better: bool = True) -> tuple[str, str]:
    """``matched`` when ``ours / paper`` lies within [1/factor, factor].

    Outside, ``ours better`` or ``ours worse``: below the range is better when
    ``smaller_is_better`` (a time, an error), above it otherwise.
    """
    rule = f"ours / paper within [1/{factor:g}, {factor:g}]"
    if not (paper > 0 and ours > 0):
        return DIFFERS, rule
    ratio = ours / paper
    if 1 / factor <= ratio <= factor:
        return MATCHED, rule
    return (BETTER if (ratio < 1) == smaller_is_better else WORSE), rule


def proof_of(res: IKResult) -> str:
    """The evidence behind a result's status (a certificate's argument), or its status."""
    return res.evidence.removeprefix("proof: ") or f"status {res.status.value} ({res.reason.value})"
