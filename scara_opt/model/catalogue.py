"""The bundled robots (``robots/<name>.toml`` and the URDF generated from it) and robot files.

:func:`load_robot` takes a bundled name or a path (``.urdf``, or a DH ``.toml``);
:func:`list_robots` lists the bundled names; :func:`example_robot_data_urdf` finds a URDF of
the optional ``example-robot-data`` package.
"""

from __future__ import annotations

import stat
import tomllib
from os import PathLike
from pathlib import Path

from scara_opt.checks import describe, short_repr
from scara_opt.errors import InputError, RobotNotFoundError, URDFError
from scara_opt.model.robot import Robot
from scara_opt.model.urdf_checks import check_tip


def list_robots() -> list[str]:
    """Names of the bundled robots (``robots/<name>.toml``)."""
    from scara_opt.model.dh_file import bundled_dir

    return sorted(p.stem for p in bundled_dir().glob("*.toml"))

def load_robot(name: str | Path, tip: str | None = None) -> Robot:
    """Load a bundled robot by name, or a robot file by path (``.urdf`` or DH ``.toml``).

    Args:
        name: a name from :func:`list_robots` (e.g. ``"zavar2024"``) or a file path.
        tip: tip frame; bundled robots default to their ``"tool"`` frame.

    Raises:
        InputError: ``name`` not a str or Path or with a NUL byte, ``tip`` not a str or None.
        RobotNotFoundError: neither a bundled name nor an existing file (lists the names).
        URDFError: ``name`` is a folder or a path that cannot be looked up (too long, in a
            folder that may not be entered), or the file is malformed (see
            :meth:`Robot.from_urdf` and :func:`scara_opt.dh.load_dh`).
    """
    from scara_opt.model.dh_file import bundled_dir, load_dh

    if not isinstance(name, (str, PathLike)):
        raise InputError(f"name must be a bundled robot name ({', '.join(list_robots())}) or "
                         f"the path of a .urdf or .toml file; got {describe(name)}")
    check_tip(tip)
    if isinstance(name, str) and name in list_robots():
        folder = bundled_dir()
        dh = load_dh(folder / f"{name}.toml")
        urdf = folder / f"{name}.urdf"
        return Robot(urdf.read_text(), tip or "tool", name=name, where=f"robot {name!r}",
                     source=dh.source, notes=dh.notes,
                     metadata=tomllib.loads((folder / f"{name}.toml").read_text()))
    if "\0" in str(name):
        raise InputError(f"robot path {str(name)!r} contains a NUL byte; pass a bundled robot "
                         "name or a plain path")
    path = Path(name)
    try:
        mode = path.stat().st_mode
    except (FileNotFoundError, NotADirectoryError):
        raise RobotNotFoundError(str(name), list_robots()) from None
    except OSError as exc:  # a name too long for a path, a folder it may not enter, ...
        raise URDFError(f"robot path {short_repr(str(name))} ({len(str(name)):,} characters) "
                        f"cannot be looked up: {exc.strerror}; pass a bundled robot name "
                        f"({', '.join(list_robots())}) or the path of a .urdf or .toml file"
                        ) from None
    if stat.S_ISDIR(mode):
        raise URDFError(f"{str(name)!r} is a folder, not a robot file; pass the path of a "
                        ".urdf or .toml file, or a bundled robot name")
    if not stat.S_ISREG(mode):
        raise RobotNotFoundError(str(name), list_robots())
    if path.suffix == ".toml":
        robot = Robot.from_dh(load_dh(path), tip or "tool")
        robot.metadata = tomllib.loads(path.read_text())
        return robot
    return Robot.from_urdf(path, tip)

#: the optional package of robot descriptions, and the extra that installs it
EXAMPLE_ROBOT_DATA = "example-robot-data"

ROBOTS_EXTRA = "pip install 'scara-opt[robots]'"

def example_robot_data_urdf(relative: str) -> Path:
    """Path of a URDF shipped by the optional ``example-robot-data`` package.

    The package (version 4.4 and later) holds only the robot files, under
    ``…/share/example-robot-data/robots/``; they are found through the installed
    distribution's file list, without importing anything.

    Args:
        relative: the file's path below ``robots/``, e.g.
            ``"panda_description/urdf/panda.urdf"`` or ``"ur_description/urdf/ur5_robot.urdf"``.

    Returns:
        The absolute path of the URDF file.

    Raises:
        ModuleNotFoundError: ``example-robot-data`` is not installed (the message names
            the extra to install).
        URDFError: the package has no such file (the message lists its URDFs).
    """
    from importlib import metadata

    try:
        files = metadata.distribution(EXAMPLE_ROBOT_DATA).files or []
    except metadata.PackageNotFoundError:
        raise ModuleNotFoundError(f"{EXAMPLE_ROBOT_DATA} is not installed; {ROBOTS_EXTRA}",
                                  name=EXAMPLE_ROBOT_DATA) from None
    suffix = "/robots/" + relative.strip("/")
    match = [f for f in files if f.as_posix().endswith(suffix)]
    if not match:
        urdfs = sorted(f.as_posix().split("/robots/", 1)[1] for f in files
                       if f.suffix == ".urdf" and "/robots/" in f.as_posix())
        raise URDFError(f"{EXAMPLE_ROBOT_DATA} has no file robots/{relative}; its URDFs: "
                        f"{', '.join(urdfs)}; pass one of these paths")
    return Path(str(match[0].locate())).resolve()
