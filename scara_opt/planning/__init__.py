"""Collision-free joint paths: OMPL samples, the conservative rule proves.

* :mod:`~scara_opt.planning.planner`: :func:`plan_path` (straight if proven clear, else
  RRTConnect and PathSimplifier) and its :class:`PathPlan` result, status ``"solved"`` or
  ``"no_path"`` (a sampling planner proves nothing: never ``"unreachable"``);
* :mod:`~scara_opt.planning.ompl_backend`: OMPL's RRTConnect and PathSimplifier with every
  state and edge checked by :mod:`scara_opt.collision.continuous`.

:func:`scara_opt.plan` calls them for each ``PTP`` of a program planned in a cell, then
times the path with toppra and proves the timed trajectory clear again.
"""

from scara_opt.planning.planner import PathPlan, PlanStatus, plan_path

__all__ = ["PathPlan", "PlanStatus", "plan_path"]
