r"""The geometry of a 6R arm (or a 7R one with a joint held) as IK-Geo reads it, and its case.

The chain is written as a product of exponentials at :math:`q = 0` (Elias and Wen 2022,
§II): joint :math:`i` turns about the unit axis :math:`h_i` through the point :math:`o_i`
(both in the base frame), so that :math:`T(q) = e^{ξ_1 q_1} \cdots e^{ξ_6 q_6} M` with
:math:`M = T(0)`. Solving for :math:`G = T^* M^{-1}` (the home folded into the target)
leaves :math:`p_{01} = o_1`, :math:`p_{i,i+1} = o_{i+1} - o_i`, :math:`p_{6T} = -o_6`.
A point may slide along its axis: where two axes meet, both points are put at the
intersection, which is what makes the closed forms of :mod:`~scara_opt.ik.arm_closed_form`
possible.

Cases served (:func:`arm_case`), each also read backwards (the inverse pose
:math:`G^{-1} = e^{-ξ_6 q_6} \cdots e^{-ξ_1 q_1}`: a spherical wrist at the base, the
parallel axes at the other end):

* ``three_parallel_two_intersecting``: :math:`h_2 ∥ h_3 ∥ h_4`, :math:`h_5` meets
  :math:`h_6` (the Universal Robots arms): up to 8 branches;
* ``spherical_two_intersecting``: :math:`h_4, h_5, h_6` meet in one point (a spherical
  wrist) and :math:`h_1` meets :math:`h_2` (most industrial arms; the Panda with its last
  joint held, read backwards): up to 8;
* ``spherical_two_parallel``: a spherical wrist and :math:`h_2 ∥ h_3`: up to 8.

Anything else (a general 6R, a spherical wrist whose first axes neither meet nor are
parallel, three parallel axes whose wrist axes do not meet: IK-Geo's SP5 and SP6 cases
and its searches) is not served: :func:`arm_case` returns ``None`` and the callers fall
back to the multi-start.

A 7R arm is served with its first or its last joint held (:func:`held_arm`): the six
others must form one of the cases above; the held joint is then sampled.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from scara_opt.model.robot import Robot

Array = NDArray[np.float64]

#: axes closer than this to parallel, or lines closer than this to meeting, count as such
#: [rad, m]: published robot files give their angles to 1e-9 or better; a geometry off by
#: less leaves the closed form's answers within about this of exact, and the fast solver's
#: polish takes them to round-off
GEOMETRY_TOL = 1e-7

CASES = ("three_parallel_two_intersecting", "spherical_two_intersecting",
         "spherical_two_parallel")


@dataclass(frozen=True)
class ArmCase:
    """A 6R chain in IK-Geo's form and the closed form that solves it.

    Attributes:
        case: one of :data:`CASES`.
        H: (6, 3) unit axes in the base frame at q = 0 (flipped where ``sign`` is -1).
        P: (7, 3) :math:`p_{01}, p_{12}, …, p_{56}, p_{6T}` [m] for the identity home.
        sign: (6,) ±1: joint ``i`` of the solved chain turns by ``sign[i] * q_i``.
        reversed: the chain is the robot's read backwards (solve for the inverse pose).
    """

    case: str
    H: Array
    P: Array
    sign: Array
    reversed: bool


@dataclass(frozen=True)
class ArmModel:
    """What the arm route needs of a robot: the case, its home and the held joint.

    Attributes:
        arm: the 6R chain's case.
        home: 4×4 :math:`M = T(0)` of the robot [m].
        joints: (6,) the robot's joints the 6R chain solves, in chain order.
        held: the index of the joint sampled (7R), or ``None``.
        held_axis, held_point: that joint's axis and a point on it in the base frame.
    """

    arm: ArmCase
    home: Array
    joints: tuple[int, ...]
    held: int | None
    held_axis: Array
    held_point: Array

    @property
    def label(self) -> str:
        """The case in words, e.g. ``three_parallel_two_intersecting``, ``…, read backwards``."""
        return self.arm.case + (", read backwards" if self.arm.reversed else "")


def screw_axes(robot: Robot) -> tuple[Array, Array, Array] | None:
    """(nq, 3) axes, (nq, 3) points on them [m] in the base frame at q = 0, and M = T(0).

    ``None`` unless every joint is revolute and none is a mimic joint.
    """
    if any(j.kind != "revolute" or j.mimic for j in robot.chain):
        return None
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, np.zeros(robot.model.nq))
    H = np.array([data.oMi[j.index + 1].rotation @ j.axis for j in robot.chain])
    Pt = np.array([data.oMi[j.index + 1].translation for j in robot.chain])
    return H / np.linalg.norm(H, axis=1, keepdims=True), Pt, robot.fk(np.zeros(robot.nq))


def _parallel(a: Array, b: Array) -> bool:
    return bool(np.linalg.norm(np.cross(a, b)) < GEOMETRY_TOL)


def _meet(h1: Array, o1: Array, h2: Array, o2: Array) -> Array | None:
    """The point where the lines (h1, o1) and (h2, o2) meet, or ``None``."""
    n = np.cross(h1, h2)
    s = float(np.linalg.norm(n))
    if s < GEOMETRY_TOL or abs(float((o2 - o1) @ n)) / s > GEOMETRY_TOL:
        return None
    # o1 + t1 h1 = o2 + t2 h2, least squares (exact up to GEOMETRY_TOL)
    t = np.linalg.lstsq(np.column_stack([h1, -h2]), o2 - o1, rcond=None)[0]
    return 0.5 * (o1 + t[0] * h1 + o2 + t[1] * h2)


def _align(H: Array, sign: Array, i: int, ref: int) -> None:
    """Flip axis ``i`` (and its sign) to point along axis ``ref`` (they are parallel)."""
    if H[i] @ H[ref] < 0:
        H[i] = -H[i]
        sign[i] = -sign[i]


def _case_of(H: Array, Pt: Array) -> tuple[str, Array, Array] | None:
    """The case of a 6R chain read forwards, its points moved, and the signs; or ``None``."""
    H, Pt, sign = H.copy(), Pt.copy(), np.ones(6)
    par = [[_parallel(H[i], H[j]) for j in range(6)] for i in range(6)]
    c56 = _meet(H[4], Pt[4], H[5], Pt[5])
    if par[1][2] and par[2][3] and c56 is not None and not par[0][1] and not par[1][4]:
        Pt[4] = Pt[5] = c56
        _align(H, sign, 2, 1)
        _align(H, sign, 3, 1)
        return CASES[0], H, Pt
    c45 = _meet(H[3], Pt[3], H[4], Pt[4])
    if c45 is None or c56 is None or np.linalg.norm(c45 - c56) > GEOMETRY_TOL:
        return None
    Pt[3] = Pt[4] = Pt[5] = c56
    c12 = _meet(H[0], Pt[0], H[1], Pt[1])
    if c12 is not None:
        Pt[0] = Pt[1] = c12
        return CASES[1], H, Pt
    if par[1][2] and not par[0][1]:
        _align(H, sign, 2, 1)
        return CASES[2], H, Pt
    return None


def arm_case(H: Array, Pt: Array) -> ArmCase | None:
    """The :class:`ArmCase` of a 6R chain (axes (6, 3), points (6, 3)), forwards or backwards.

    ``None`` when neither reading is one of :data:`CASES` (see the module docstring).
    """
    for backwards in (False, True):
        Hc, Pc = (-H[::-1], Pt[::-1]) if backwards else (H, Pt)
        found = _case_of(Hc, Pc)
        if found is not None:
            case, Hs, Os = found
            sign = np.sign(np.einsum("ij,ij->i", Hs, Hc))
            P = np.vstack([Os[0], np.diff(Os, axis=0), -Os[-1]])
            return ArmCase(case, Hs, P, sign, backwards)
    return None


def arm_model(robot: Robot) -> ArmModel | None:
    """The arm route's model of ``robot`` (cached on it), or ``None`` where none serves.

    A 6R arm of one of :data:`CASES`; a 7R arm whose first or last joint held leaves one
    (the last is tried first, as in the Panda's analytic IK of He and Liu, 2021).
    """
    cache = robot.__dict__
    if "_arm_model" not in cache:
        cache["_arm_model"] = _arm_model(robot)
    return cache["_arm_model"]


def _arm_model(robot: Robot) -> ArmModel | None:
    axes = screw_axes(robot)
    if axes is None or robot.nq not in (6, 7):
        return None
    H, Pt, M = axes
    if robot.nq == 6:
        arm = arm_case(H, Pt)
        return None if arm is None else ArmModel(arm, M, tuple(range(6)), None,
                                                 np.zeros(3), np.zeros(3))
    for held in (6, 0):
        keep = [k for k in range(7) if k != held]
        arm = arm_case(H[keep], Pt[keep])
        if arm is not None:
            return ArmModel(arm, M, tuple(keep), held, H[held], Pt[held])
    return None
