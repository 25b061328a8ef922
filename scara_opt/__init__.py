"""scara_opt: model-based kinematics and trajectories of SCARA robots and any serial URDF chain.

Robots are URDFs loaded into Pinocchio (:class:`Robot`); the bundled ones are
generated from the papers' DH tables (:func:`load_robot`, :func:`list_robots`).

Every public name and submodule is an attribute of the package (``so.solve_ik``,
``so.plots``, ``so.workspace``…), imported at its first use: ``import scara_opt`` itself
loads nothing heavy (the command line starts fast, and a Ctrl-C while the libraries load
is the command's own, one line).
"""

from __future__ import annotations

import importlib
import logging
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

logging.getLogger(__name__).addHandler(logging.NullHandler())

#: public name -> the module that defines it (imported at the name's first use)
_EXPORTS = {
    "compare": "scara_opt.comparison",
    **dict.fromkeys(("BranchError", "DynamicsError", "FrameNotFoundError", "InputError",
                     "JointLimitError", "MoveError", "RobotNotFoundError", "ScaraOptError",
                     "SolverOptionError", "TargetError", "TrajectoryError", "UnknownSolverError",
                     "URDFError", "CellError", "CollisionError", "MeshNotFoundError",
                     "MoveCollisionError", "NoPathFoundError", "ProgramError",
                     "UnknownBodyError"),
                    "scara_opt.errors"),
    **dict.fromkeys(("Box", "Capsule", "Cell", "CollisionChecker", "Cylinder", "Mesh",
                     "Sphere", "load_cell"), "scara_opt.collision"),
    **dict.fromkeys(("CompilingWarning", "FallbackWarning", "NativeCodeWarning",
                     "ScaraOptWarning"), "scara_opt.errors"),
    **dict.fromkeys(("CIRC", "LIN", "PTP", "MotionTrajectory", "Program", "ToolLimits",
                     "cycle_time", "load_program", "plan"), "scara_opt.motion"),
    **dict.fromkeys(("IKResult", "Reason", "Status", "get_solver", "ik_all", "register_solver",
                     "solve_ik", "solvers"), "scara_opt.ik"),
    **dict.fromkeys(("BatchResult", "solve_many"), "scara_opt.ik.lm_batch"),
    **dict.fromkeys(("Robot", "list_robots", "load_robot"), "scara_opt.model"),
    "Target": "scara_opt.target",
    **dict.fromkeys(("JointPath", "Trajectory", "ik_path", "time_parameterize",
                     "timing_methods"), "scara_opt.trajectory"),
    "Footprint": "scara_opt.footprint",
    **dict.fromkeys(("Workspace", "workspace"), "scara_opt.workspace_analysis"),
}

#: public submodules, imported at first attribute access
_LAZY = ("cli", "collision", "comparison", "footprint", "ik", "metaheuristics", "model",
         "motion", "paths", "planning", "plots", "pose", "reports", "trajectory", "view",
         "workspace_analysis")

__all__ = [
    "__version__", "BatchResult", "BranchError", "CIRC", "LIN", "MotionTrajectory", "MoveError",
    "plan", "PTP", "ToolLimits", "cycle_time", "compare", "DynamicsError", "Footprint",
    "FrameNotFoundError", "get_solver", "ik_all", "ik_path", "IKResult", "InputError",
    "JointLimitError", "JointPath",
    "list_robots", "load_robot", "paths", "pose", "register_solver", "Robot", "Reason",
    "RobotNotFoundError", "ScaraOptError", "solve_ik", "solve_many", "SolverOptionError",
    "solvers", "Status", "Target", "TargetError", "time_parameterize", "timing_methods",
    "Trajectory", "TrajectoryError", "UnknownSolverError", "URDFError", "Workspace", "workspace",
    "Box", "Capsule", "Cell", "CellError", "CollisionChecker", "CollisionError", "Cylinder",
    "load_cell", "Mesh", "MeshNotFoundError", "MoveCollisionError", "NoPathFoundError",
    "Sphere", "UnknownBodyError", "load_program", "Program", "ProgramError",
    "CompilingWarning", "FallbackWarning", "NativeCodeWarning", "ScaraOptWarning",
]


def __getattr__(name: str) -> Any:
    """The public names and submodules, imported on first use (then cached here)."""
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
    elif name in _LAZY:
        value = importlib.import_module(f"scara_opt.{name}")
    else:
        raise AttributeError(f"module 'scara_opt' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_EXPORTS, *_LAZY})


if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from scara_opt import paths, pose
    from scara_opt.collision import (
        Box,
        Capsule,
        Cell,
        CollisionChecker,
        Cylinder,
        Mesh,
        Sphere,
        load_cell,
    )
    from scara_opt.comparison import compare
    from scara_opt.errors import (
        BranchError,
        CellError,
        CollisionError,
        DynamicsError,
        FrameNotFoundError,
        InputError,
        JointLimitError,
        MeshNotFoundError,
        MoveCollisionError,
        MoveError,
        NoPathFoundError,
        ProgramError,
        RobotNotFoundError,
        ScaraOptError,
        SolverOptionError,
        TargetError,
        TrajectoryError,
        UnknownBodyError,
        UnknownSolverError,
        URDFError,
    )
    from scara_opt.footprint import Footprint
    from scara_opt.ik import (
        IKResult,
        Reason,
        Status,
        get_solver,
        ik_all,
        register_solver,
        solve_ik,
        solvers,
    )
    from scara_opt.ik.lm_batch import BatchResult, solve_many
    from scara_opt.model import Robot, list_robots, load_robot
    from scara_opt.motion import (
        CIRC,
        LIN,
        PTP,
        MotionTrajectory,
        Program,
        ToolLimits,
        cycle_time,
        load_program,
    )
    from scara_opt.motion.plan import plan  # mypy reads motion's `plan` as the submodule
    from scara_opt.target import Target
    from scara_opt.trajectory import (
        JointPath,
        Trajectory,
        ik_path,
        time_parameterize,
        timing_methods,
    )
    from scara_opt.workspace_analysis import Workspace, workspace
