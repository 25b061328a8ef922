"""Robot files: a DH table in TOML (``robots/<name>.toml``) read into a :class:`DHRobot`.

Values are in the file's own units (``length_unit``, ``angle_unit``) and converted to SI;
unknown or misspelt keys are refused. ``python -m scara_opt.dh`` regenerates every
bundled URDF (:func:`regenerate`).
"""

from __future__ import annotations

import difflib
import math
import tomllib
from pathlib import Path

import numpy as np
import pinocchio as pin

from scara_opt.errors import JointLimitError, URDFError
from scara_opt.model.citation import check_citation
from scara_opt.model.dh import (
    ANGLE_UNITS,
    FILE_KEYS,
    JOINT_KEYS,
    LENGTH_UNITS,
    TOOL_KEYS,
    DHJoint,
    DHRobot,
    dh_to_urdf,
)
from scara_opt.model.inertial import check_inertial, inertia_matrix

__all__ = ["bundled_dir", "check_keys", "collision_radii", "load_dh", "main", "read_toml",
           "regenerate"]


def read_toml(path: Path, where: str, what: str, error: type[Exception] = URDFError) -> dict:
    """The parsed TOML file at ``path``.

    Raises:
        URDFError: (or ``error``) a missing or unreadable file, not UTF-8, not valid TOML;
            ``where`` names the file, ``what`` what to pass instead.
    """
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise error(f"{where} does not exist; check the path") from None
    except UnicodeDecodeError as exc:
        raise error(f"{where} is not UTF-8 text ({exc.reason} at byte {exc.start}); pass "
                    f"{what}") from None
    except OSError as exc:
        raise error(f"{where} cannot be read ({exc.strerror}); pass {what}") from None
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{where} is not valid TOML: {exc}") from None


def check_keys(table: dict, accepted: tuple[str, ...], where: str,
               error: type[Exception] = URDFError) -> None:
    """Refuse keys a robot (or cell) file does not know (a misspelt key would be ignored).

    Raises:
        URDFError: (or ``error``) naming the unknown keys, a close match, the accepted keys.
    """
    unknown = [k for k in table if k not in accepted]
    if unknown:
        hints = "".join(f" ({k!r}: did you mean {m[0]!r}?)" for k in unknown
                        if (m := difflib.get_close_matches(k, accepted, 1)))
        raise error(f"{where} has unknown key(s) {', '.join(map(repr, unknown))}{hints}; "
                        f"accepted keys: {', '.join(accepted)}; fix or remove them")


def _finite(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _number(row: dict, key: str, where: str, default: float = 0.0) -> float:
    value = row.get(key, default)
    if not _finite(value):
        raise URDFError(f"{where}: {key} must be a finite number, got {value!r}")
    return float(value)


def _vector(table: dict, key: str, where: str) -> np.ndarray:
    value = table.get(key, [0, 0, 0])
    if not (isinstance(value, list) and len(value) == 3 and all(map(_finite, value))):
        raise URDFError(f"{where}: {key} must be a list of 3 finite numbers, got {value!r}")
    return np.array(value, float)


def _inertial(row: dict, at: str, L: float) -> dict:
    """A row's optional mass [kg], com [length unit], inertia [kg·m²] and effort [N·m or N].

    Raises:
        URDFError: a non-finite or mis-shaped entry, mass or effort <= 0, com or inertia
            without mass, an inertia no body has (naming the joint and the value).
    """
    out: dict = {}
    for key in ("mass", "effort"):
        if key in row:
            value = _number(row, key, at)
            if value <= 0:
                what = "[kg]" if key == "mass" else "[N·m for revolute, N for prismatic]"
                raise URDFError(f"{at}: {key} must be > 0 {what}, got {row[key]!r}; give the "
                                f"estimate or leave {key} out")
            out[key] = value
    if ("com" in row or "inertia" in row) and "mass" not in row:
        raise URDFError(f"{at}: com and inertia describe a mass: add mass = ... [kg]")
    if "mass" in out:
        out["com"] = tuple(_vector(row, "com", at) * L)
        six = row.get("inertia", [0.0] * 6)
        if not (isinstance(six, list) and len(six) == 6 and all(map(_finite, six))):
            raise URDFError(f"{at}: inertia must be a list of 6 finite numbers (ixx, ixy, ixz, "
                            f"iyy, iyz, izz) [kg·m²], got {six!r}")
        out["inertia"] = tuple(float(v) for v in six)
        check_inertial(at, out["mass"], np.array(out["com"]), inertia_matrix(six),
                       out.get("effort", 0.0))
    return out


def _text(table: dict, key: str, where: str, default: str) -> str:
    """A text entry (name, title, source, ...): a TOML string, or ``default`` when absent."""
    value = table.get(key, default)
    if not isinstance(value, str):
        raise URDFError(f"{where}: {key} must be a string (in quotes), got {value!r}")
    return value


def _table(value: object, where: str) -> dict:
    if not isinstance(value, dict):
        raise URDFError(f"{where} must be a TOML table (key = value lines), got {value!r}")
    return value


def _check_limits(row: dict, at: str, name: str, unit: str) -> None:
    """Refuse a joint's limits in the file's own units (``unit`` of the joint variable).

    Raises:
        JointLimitError: a lower limit not below the upper one, or a velocity or
            acceleration limit <= 0, quoted as the file gives them.
    """
    lower, upper = _number(row, "lower", at), _number(row, "upper", at)
    if not lower < upper:
        raise JointLimitError(f"{at}: lower limit {lower:g} {unit} is not below upper limit "
                              f"{upper:g} {unit}; swap them or fix the robot file", joint=name)
    for key, per in (("velocity", "/s"), ("acceleration", "/s^2")):
        value = _number(row, key, at, 1.0)
        if not value > 0:
            raise JointLimitError(f"{at}: {key} limit {value:g} {unit}{per} must be > 0; fix "
                                  "the robot file", joint=name)


def load_dh(path: str | Path) -> DHRobot:
    """Read a robot file (TOML with a DH table in stated units) into SI units.

    Args:
        path: a ``.toml`` file with ``length_unit``, ``angle_unit``, ``convention``,
            ``[[joints]]`` rows and optional ``[tool]`` (``xyz``, ``rpy``), ``[footprint]``
            (read by :class:`~scara_opt.Footprint`) and ``[citation]``
            (:mod:`scara_opt.model.citation`); the keys allowed are :data:`FILE_KEYS`,
            :data:`JOINT_KEYS` and :data:`TOOL_KEYS`. A row's optional ``mass`` [kg], ``com``
            [length_unit, in the joint's moving frame], ``inertia`` (ixx, ixy, ixz, iyy, iyz,
            izz) [kg·m², about the com] and ``effort`` [N·m or N] go to the URDF's
            ``<inertial>`` and ``<limit effort=>``. A row's optional ``radius``
            [length_unit] is the radius of the collision capsules of the link the joint
            moves (:mod:`scara_opt.collision.geometry`; it does not enter the URDF).

    Raises:
        URDFError: missing file, TOML syntax, unknown key, unit or joint type, bad or
            non-finite entries; mass, effort or radius <= 0, an inertia no body has; an incomplete
            ``[citation]``.
        JointLimitError: a lower limit not below its upper limit, or a limit <= 0.
    """
    path = Path(path)
    where = f"robot file {str(path)!r}"
    data = read_toml(path, where, "a TOML robot file")
    check_keys(data, FILE_KEYS, where)
    lu, au = data.get("length_unit"), data.get("angle_unit")
    if not (isinstance(lu, str) and lu in LENGTH_UNITS and isinstance(au, str)
            and au in ANGLE_UNITS):
        raise URDFError(
            f"{where}: length_unit must be one of {sorted(LENGTH_UNITS)} and "
            f"angle_unit one of {sorted(ANGLE_UNITS)}; got {lu!r} and {au!r}"
        )
    L, A = LENGTH_UNITS[lu], ANGLE_UNITS[au]
    rows = data.get("joints")
    if not isinstance(rows, list) or not rows:
        raise URDFError(f"{where} has no [[joints]] rows")
    joints = []
    for i, row in enumerate(rows):
        row = _table(row, f"{where}: joints entry {i + 1}")
        name = _text(row, "name", f"{where}: joints entry {i + 1}", f"joint{i + 1}")
        at = f"{where}: joint {name!r}"
        check_keys(row, JOINT_KEYS, at)
        jtype = _text(row, "type", at, "")
        unit = A if jtype == "revolute" else L  # unit of the joint variable
        if "radius" in row and not _number(row, "radius", at) > 0:
            raise URDFError(f"{at}: radius must be > 0 [{lu}] (the collision capsule of the "
                            f"link the joint moves), got {row['radius']!r}; give the link's "
                            "half-width or leave radius out")
        if jtype in ("revolute", "prismatic"):  # another type: DHJoint says what is wrong
            _check_limits(row, at, name, au if jtype == "revolute" else lu)
        joints.append(
            DHJoint(
                name=name,
                type=jtype,
                a=_number(row, "a", at) * L,
                alpha=_number(row, "alpha", at) * A,
                d=_number(row, "d", at) * L,
                theta=_number(row, "theta", at) * A,
                sign=_number(row, "sign", at, 1.0),
                lower=_number(row, "lower", at) * unit,
                upper=_number(row, "upper", at) * unit,
                velocity=_number(row, "velocity", at, 1.0) * unit,
                acceleration=_number(row, "acceleration", at, 1.0) * unit,
                **_inertial(row, at, L),
            )
        )
    tool = np.eye(4)
    if "tool" in data:
        table = _table(data["tool"], f"{where}: [tool]")
        check_keys(table, TOOL_KEYS, f"{where}: [tool]")
        tool[:3, :3] = pin.rpy.rpyToMatrix(_vector(table, "rpy", f"{where}: [tool]") * A)
        tool[:3, 3] = _vector(table, "xyz", f"{where}: [tool]") * L
    _text(data, "title", where, "")
    _text(data, "dynamics_source", where, "")
    if "citation" in data:
        check_citation(data["citation"], where)
    return DHRobot(
        name=_text(data, "name", where, path.stem),
        joints=tuple(joints),
        convention=_text(data, "convention", where, "standard"),
        tool=tool,
        source=_text(data, "source", where, ""),
        notes=_text(data, "notes", where, ""),
    )


def collision_radii(metadata: dict) -> dict[str, float]:
    """The ``radius`` of each ``[[joints]]`` row of a parsed robot file, in metres, by joint name.

    Rows without one are left out (an empty dict for a URDF robot). The values were checked
    by :func:`load_dh` (finite, > 0).
    """
    L = LENGTH_UNITS.get(metadata.get("length_unit", "m"), 1.0)
    rows = metadata.get("joints", [])
    return {row.get("name", f"joint{i + 1}"): float(row["radius"]) * L
            for i, row in enumerate(rows) if isinstance(row, dict) and "radius" in row}


def bundled_dir() -> Path:
    """The folder of the bundled robot files (installed wheel or source checkout)."""
    here = Path(__file__).resolve().parent
    for candidate in (here.parent / "robots", here.parent.parent / "robots"):
        if candidate.is_dir():
            return candidate
    raise URDFError("the bundled robots folder is missing; reinstall scara-opt")


def regenerate(folder: Path | None = None) -> list[Path]:
    """Rewrite ``<name>.urdf`` beside every ``<name>.toml`` in ``folder``; return the paths."""
    folder = bundled_dir() if folder is None else Path(folder)
    written = []
    for toml_path in sorted(folder.glob("*.toml")):
        urdf = toml_path.with_suffix(".urdf")
        urdf.write_text(dh_to_urdf(load_dh(toml_path)))
        written.append(urdf)
    return written


def main() -> int:
    """``python -m scara_opt.dh``: regenerate every bundled URDF; returns the exit code."""
    for p in regenerate():
        print(f"wrote {p}")
    return 0
