"""Kept for compatibility: the robot model lives in :mod:`scara_opt.model` (re-exported here).

``from scara_opt.robot import Robot, load_robot`` keeps working; new code imports from
:mod:`scara_opt.model` (or uses ``so.Robot``, ``so.load_robot``).
"""

from scara_opt.model import (  # noqa: F401  (re-exports)
    EXAMPLE_ROBOT_DATA,
    ROBOTS_EXTRA,
    Array,
    ChainJoint,
    Robot,
    example_robot_data_urdf,
    list_robots,
    load_robot,
)
