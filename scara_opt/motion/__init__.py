"""Motion programs as a SCARA cell runs them: PTP / LIN / CIRC moves, tool limits, one trajectory.

``plan(robot, [PTP(...), LIN(...), CIRC(via, goal)], ToolLimits(speed=0.25))`` gives one
rest-to-rest :class:`~scara_opt.Trajectory`, time-optimal (TOPP-RA) under the joint velocity
and acceleration limits and the tool's speed, acceleration and yaw rate, checked at 1 kHz.
With ``cell=`` the program is planned in a cell: PTPs around its obstacles, every section
proven clear of them (:mod:`scara_opt.motion.clearance`). A program file (TOML, in the
units it states) is read by ``load_program(path)`` (:mod:`scara_opt.motion.program_file`).
"""

from scara_opt.motion.cycle import CycleResult, cycle_time
from scara_opt.motion.moves import CIRC, LIN, PTP, Move
from scara_opt.motion.plan import plan
from scara_opt.motion.program_file import Program, load_program
from scara_opt.motion.result import MotionTrajectory
from scara_opt.motion.tool_limits import ToolLimits

__all__ = ["CIRC", "CycleResult", "LIN", "PTP", "Move", "MotionTrajectory", "Program",
           "ToolLimits", "cycle_time", "load_program", "plan"]
