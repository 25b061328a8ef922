"""The robot model: from a URDF or a DH table to a :class:`Robot` and its forward kinematics.

One module per job:

* :mod:`~scara_opt.model.urdf_checks`: URDF validation (XML, tree, joints, limits, axes,
  mimics, the toolkit's ``<scara_opt>`` extension), before Pinocchio sees the file;
* :mod:`~scara_opt.model.urdf_tree`: the chain to the tip as a Pinocchio model (locked,
  continuous and mimic joints);
* :mod:`~scara_opt.model.robot`: the :class:`Robot` (Pinocchio FK and Jacobians, limits);
* :mod:`~scara_opt.model.joint_checks`, :mod:`~scara_opt.model.tool_angle`: the Robot's
  checks of joint values, and its planar tool angle (yaw);
* :mod:`~scara_opt.model.copies`: a Robot with new limits, and pickling;
* :mod:`~scara_opt.model.symbolic`: the casadi expression of the FK;
* :mod:`~scara_opt.model.batch_fk`: the one vectorised FK route (compiled casadi, mapped);
* :mod:`~scara_opt.model.compiled`: casadi Functions compiled once per machine and cached;
* :mod:`~scara_opt.model.buffers`: casadi Functions evaluated in place on numpy arrays;
* :mod:`~scara_opt.model.dh`: standard / modified DH tables to URDF;
* :mod:`~scara_opt.model.dh_file`: robot files (a DH table in TOML) read and checked;
* :mod:`~scara_opt.model.catalogue`: the bundled robots and :func:`load_robot`.
"""

from scara_opt.model.catalogue import (
    EXAMPLE_ROBOT_DATA,
    ROBOTS_EXTRA,
    example_robot_data_urdf,
    list_robots,
    load_robot,
)
from scara_opt.model.robot import Array, ChainJoint, Robot

__all__ = ["EXAMPLE_ROBOT_DATA", "ROBOTS_EXTRA", "Array", "ChainJoint", "Robot",
           "example_robot_data_urdf", "list_robots", "load_robot"]
