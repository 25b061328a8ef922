"""scara_opt: model-based kinematics and trajectories of SCARA robots and any serial URDF chain.

Robots are URDFs loaded into Pinocchio (:class:`Robot`); the bundled ones are
generated from the papers' DH tables (:func:`load_robot`, :func:`list_robots`).

Every public submodule is an attribute of the package (``so.plots``, ``so.workspace``…);
the ones that pull heavy libraries (matplotlib) are imported at first use.
"""

import importlib
import logging
from typing import Any

from scara_opt import metaheuristics, paths  # noqa: F401  (metaheuristics register themselves)
from scara_opt.comparison import compare
from scara_opt.errors import (
    BranchError,
    FrameNotFoundError,
    InputError,
    JointLimitError,
    MoveError,
    RobotNotFoundError,
    ScaraOptError,
    SolverOptionError,
    TargetError,
    TrajectoryError,
    UnknownSolverError,
    URDFError,
)
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
from scara_opt.motion import CIRC, LIN, PTP, MotionTrajectory, ToolLimits, cycle_time, plan
from scara_opt.target import Target
from scara_opt.trajectory import (
    JointPath,
    Trajectory,
    ik_path,
    time_parameterize,
    timing_methods,
)
from scara_opt.workspace_analysis import Footprint, Workspace, workspace

__version__ = "0.1.0"

logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = [
    "__version__",
    "BatchResult",
    "BranchError",
    "CIRC",
    "LIN",
    "MotionTrajectory",
    "MoveError",
    "plan",
    "PTP",
    "ToolLimits",
    "compare",
    "cycle_time",
    "Footprint",
    "FrameNotFoundError",
    "get_solver",
    "ik_all",
    "ik_path",
    "IKResult",
    "InputError",
    "JointLimitError",
    "JointPath",
    "list_robots",
    "load_robot",
    "paths",
    "register_solver",
    "Robot",
    "Reason",
    "RobotNotFoundError",
    "ScaraOptError",
    "solve_ik",
    "solve_many",
    "SolverOptionError",
    "solvers",
    "Status",
    "Target",
    "TargetError",
    "time_parameterize",
    "timing_methods",
    "Trajectory",
    "TrajectoryError",
    "UnknownSolverError",
    "URDFError",
    "Workspace",
    "workspace",
]

#: public submodules imported at first attribute access (they import matplotlib or pandas)
_LAZY = ("cli", "comparison", "dh", "model", "plots", "reports", "robot",
         "workspace_analysis")


def __getattr__(name: str) -> Any:
    """``so.plots`` and the other public submodules, imported on first use."""
    if name in _LAZY:
        return importlib.import_module(f"scara_opt.{name}")
    raise AttributeError(f"module 'scara_opt' has no attribute {name!r}")
