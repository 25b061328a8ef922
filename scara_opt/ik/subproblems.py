r"""IK-Geo's canonical subproblems, symbolic (casadi SX), for the closed forms of 6R arms.

Elias and Wen (2022), *IK-Geo: Unified robot inverse kinematics using subproblem
decomposition*, arXiv:2211.05737, §III. :math:`R(k, θ)` is the rotation by :math:`θ`
about the unit axis :math:`k`. Each function returns every solution as a fixed number of
candidates (a branch of a closed form is then one fixed column of casadi's output);
where a subproblem has no exact solution, its candidates are the least-squares ones
(two equal candidates): the caller keeps only branches that the forward kinematics
confirms.

* SP1, :func:`sp1`: :math:`R(k, θ) p_1 = p_2` (one θ);
* SP2, :func:`sp2`: :math:`R(k_1, θ_1) p_1 = R(k_2, θ_2) p_2` (two pairs);
* SP3, :func:`sp3`: :math:`\|R(k, θ) p_1 - p_2\| = d` (two θ);
* SP4, :func:`sp4`: :math:`h^T R(k, θ) p = d` (two θ).

SP5 and SP6 (the quartics of the general spherical-wrist and three-parallel arms) are not
here: the arms they serve fall back to the multi-start (:mod:`scara_opt.ik.arm_geometry`
says which arms are served).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

Vec = ca.SX | np.ndarray


def _sx(v: Vec) -> ca.SX:
    return v if isinstance(v, ca.SX) else ca.SX(np.asarray(v, dtype=float))


def rot(k: Vec, theta: ca.SX) -> ca.SX:
    """3×3 rotation about the unit axis ``k`` by ``theta`` [rad] (Rodrigues)."""
    k = _sx(k)
    K = ca.skew(k)
    return ca.SX.eye(3) + ca.sin(theta) * K + (1 - ca.cos(theta)) * (K @ K)


def sp1(p1: Vec, p2: Vec, k: Vec) -> ca.SX:
    r"""θ with :math:`R(k, θ) p_1 = p_2` (least squares where none is exact).

    :math:`R p_1 = (k·p_1) k + \cos θ\, p_⊥ + \sin θ\, (k × p_1)` with
    :math:`p_⊥ = -k × (k × p_1)`: θ is the angle of :math:`p_2` in the plane of
    :math:`p_⊥` and :math:`k × p_1` (0 where :math:`p_1` lies along :math:`k`: any θ).
    """
    p1, p2, k = _sx(p1), _sx(p2), _sx(k)
    kxp = ca.cross(k, p1)
    return ca.atan2(ca.dot(kxp, p2), ca.dot(-ca.cross(k, kxp), p2))


def sp4(h: Vec, p: Vec, k: Vec, d: ca.SX | float) -> tuple[ca.SX, ca.SX]:
    r"""The two θ with :math:`h^T R(k, θ) p = d` (least squares where none is exact).

    :math:`h^T R p = (k·p)(h·k) + a_1 \sin θ + a_2 \cos θ = |a| \cos(θ - φ) + c`,
    :math:`φ = \operatorname{atan2}(a_1, a_2)`; so :math:`θ = φ ± \operatorname{atan2}
    (\sqrt{|a|^2 - b^2}, b)`, :math:`b = d - c` (the root clamped at 0: the least-squares
    θ = φ, twice, where :math:`|b| > |a|`).
    """
    h, p, k = _sx(h), _sx(p), _sx(k)
    kxp = ca.cross(k, p)
    a1 = ca.dot(h, kxp)
    a2 = ca.dot(h, -ca.cross(k, kxp))
    b = d - ca.dot(k, p) * ca.dot(h, k)
    phi = ca.atan2(a1, a2)
    half = ca.atan2(ca.sqrt(ca.fmax(a1 * a1 + a2 * a2 - b * b, 0.0)), b)
    return phi + half, phi - half


def sp3(p1: Vec, p2: Vec, k: Vec, d: ca.SX | float) -> tuple[ca.SX, ca.SX]:
    r"""The two θ with :math:`\|R(k, θ) p_1 - p_2\| = d`.

    SP4 of :math:`p_2^T R(k, θ) p_1 = (\|p_1\|^2 + \|p_2\|^2 - d^2) / 2`.
    """
    p1, p2 = _sx(p1), _sx(p2)
    return sp4(p2, p1, k, (ca.dot(p1, p1) + ca.dot(p2, p2) - d * d) / 2)


def sp2(p1: Vec, p2: Vec, k1: Vec, k2: Vec) -> tuple[tuple[ca.SX, ca.SX], tuple[ca.SX, ca.SX]]:
    r"""The two pairs :math:`(θ_1, θ_2)` with :math:`R(k_1, θ_1) p_1 = R(k_2, θ_2) p_2`.

    :math:`θ_1` by SP4 (:math:`k_2^T R(k_1, θ_1) p_1 = k_2^T p_2`: the common vector keeps
    its component along :math:`k_2`), then each :math:`θ_2` by SP1.
    """
    p1, p2, k1, k2 = _sx(p1), _sx(p2), _sx(k1), _sx(k2)
    out = []
    for t1 in sp4(k2, p1, k1, ca.dot(k2, p2)):
        out.append((t1, sp1(p2, rot(k1, t1) @ p1, k2)))
    return out[0], out[1]
