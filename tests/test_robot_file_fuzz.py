"""Malformed robot files, generated: each loads into a working Robot or raises a ScaraOptError.

Hypothesis (derandomized: the same examples every run) mutates the text of the bundled
robots: URDFs element by element (deleted, duplicated or renamed elements, garbage attribute
values, extra ``<scara_opt>`` elements, truncation) and DH TOML files line by line (deleted
or duplicated lines, garbage values, stray keys and tables). Whatever comes out, loading it
must either give a Robot whose FK works at a mid-range configuration (and whose
``[footprint]``, if any, reads cleanly) or raise an error of the scara_opt family; never a
bare ValueError, TypeError, KeyError, ...
"""

from __future__ import annotations

import copy
import logging
import xml.etree.ElementTree as ET

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import scara_opt as so
from scara_opt.footprint import Footprint

from .conftest import BUNDLED, DATA, ROOT

URDF_SOURCES = [ROOT / "robots" / f"{name}.urdf" for name in BUNDLED] + [
    DATA / "mimic_arm.urdf", DATA / "continuous_arm.urdf", DATA / "gripper_arm.urdf"]
TOML_SOURCES = [ROOT / "robots" / f"{name}.toml" for name in BUNDLED]

#: attribute values a fuzzer would try: text, empty, NaN/inf, huge, tiny, zero, negative,
#: too few or too many numbers
GARBAGE = ["abc", "", " ", "nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e400", "0", "-0",
           "-0.0", "-5", "1e-320", "1 2", "1 2 3 4", "0 0 0", "nan 0 0", "0 0 inf", "1e308 0 0",
           "true", "0x10", "1,5", "tool", "base_link", "revolute", "fixed", "continuous",
           "prismatic", "floating"]
ATTRIBUTES = ["name", "type", "link", "xyz", "rpy", "lower", "upper", "velocity", "effort",
              "acceleration", "joint", "multiplier", "offset", "filename"]
TAGS = ["joint", "link", "limit", "axis", "origin", "parent", "child", "scara_opt", "mimic",
        "robot", "foo"]

#: TOML values a fuzzer would try (TOML has nan and inf literals)
TOML_GARBAGE = ["nan", "inf", "-inf", "1e308", "-1e308", "0", "-0.0", "-5", "1e-320", "1",
                "123456789012345678901234567890", '"abc"', '""', '"12"', "true", "false",
                "[1, 2]", "[1, 2, 3]", '[1, "a", 3]', "[nan, 0, 0]", "[[0, 0], [1, 0]]", "[]",
                "{a = 1}", "{}", '"m"', '"mm"', '"deg"', '"rad"', '"revolute"', '"fixed"',
                '"prismatic"', '"continuous"', '"modified"', '"circle"', '"polygon"',
                '"theta1"', "1979-05-27"]
TOML_LINES = ["acceleration = nan", "acceleration = -5", "acceleration = 0", "velocity = inf",
              "velocity = true", 'acceleration = "fast"', "[footprint]", 'shape = "circle"',
              'shape = "polygon"', "radius = -1", "radius = 1e308", "radius = true",
              "center = [1, 2]", 'center = [1, "a"]', "center = [true, false]",
              "vertices = [[0, 0], [1, 0], [1, 1]]", "vertices = [[0, 0], [1, nan], [1, 1]]",
              "vertices = 5", "links_from = 3", 'links_from = "nowhere"', '[tool]',
              "xyz = [1, 2]", "xyz = [1, 2, nan]", "rpy = [1e308, 0, 0]", "rpy = 1",
              "[[joints]]", "name = 5", 'name = "theta1"', 'type = "revolute"', "a = 1e308",
              "d = 1e308", "sign = -1", "sign = 0", "lower = 1e308", "upper = 1e308",
              "upper = -1e308", "length_unit = 5", 'angle_unit = "grad"', "convention = 1",
              "joints = 5", "tool = 5", "footprint = 5", "typo = 1", "[extra]"]


#: URDF mutation kinds, weighted toward the subtle ones (a bad value in a file that still
#: parses) over the blunt ones (a truncated file fails at the XML parser)
MUTATION_KINDS = ["attribute"] * 4 + ["extension"] * 2 + ["delete", "duplicate", "rename",
                                                          "truncate"]


def _urdf_mutation(root: ET.Element, data: st.DataObject) -> str:
    """Apply one structural mutation to ``root`` (in place) and return the new text."""
    elements = [e for e in root.iter() if e is not root]
    kind = data.draw(st.sampled_from(MUTATION_KINDS))
    target = data.draw(st.sampled_from(elements))
    parent = next(p for p in root.iter() if target in list(p))
    if kind == "delete":
        parent.remove(target)
    elif kind == "duplicate":
        parent.insert(list(parent).index(target) + 1, copy.deepcopy(target))
    elif kind == "attribute":
        own = sorted(target.attrib) or ATTRIBUTES
        name = data.draw(st.sampled_from(own * 3 + ATTRIBUTES))
        value = data.draw(st.sampled_from(GARBAGE) | st.floats().map(repr) | st.text(max_size=5))
        target.set(name, value)
    elif kind == "rename":
        target.tag = data.draw(st.sampled_from(TAGS))
    elif kind == "extension":
        joints = [e for e in root.iter("joint")]
        host = data.draw(st.sampled_from(joints + [target]))
        ext = ET.SubElement(host, "scara_opt")
        ext.set(data.draw(st.sampled_from(["acceleration", "accel", "velocity"])),
                data.draw(st.sampled_from(GARBAGE) | st.floats().map(repr)))
    text = ET.tostring(root, encoding="unicode")
    if kind == "truncate":
        text = text[:data.draw(st.integers(0, len(text)))]
    return text


def _check_loaded(robot: so.Robot) -> None:
    """A loaded robot works: FK at a mid-range q, finite limits where the file gives them."""
    q = 0.5 * (robot.sampling_lower + robot.sampling_upper)
    T = robot.fk(q)
    assert T.shape == (4, 4)
    assert np.isfinite(T).all(), "a loaded robot's FK must be finite"
    acc, vel = robot.acceleration_limit, robot.velocity_limit
    assert not np.isnan(acc).any() and (acc > 0).all()
    assert not np.isnan(vel).any() and (vel > 0).all()
    Footprint.from_robot(robot)  # may raise URDFError; must not raise anything else


@settings(max_examples=250, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_mutated_urdf_loads_or_raises_a_scara_opt_error(data, tmp_path_factory):
    """Mutated URDFs of bundled and test robots: a working Robot or a ScaraOptError.

    Mutation: the <scara_opt acceleration> element read with a bare float(), as before
    (abc -> ValueError; NaN, -5, 0 loaded silently) -> fails.
    """
    source = data.draw(st.sampled_from(URDF_SOURCES))
    root = ET.fromstring(source.read_text())
    for _ in range(data.draw(st.sampled_from([1, 1, 1, 2, 3]))):
        text = _urdf_mutation(root, data)
        try:
            root = ET.fromstring(text)
        except ET.ParseError:
            break
    tip = data.draw(st.sampled_from([None, "tool"]))
    path = tmp_path_factory.mktemp("urdf") / "robot.urdf"
    path.write_text(text)
    logging.disable(logging.WARNING)
    try:
        robot = so.Robot.from_urdf(path, tip)
    except so.ScaraOptError:
        return
    finally:
        logging.disable(logging.NOTSET)
    _check_loaded(robot)


@settings(max_examples=250, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_mutated_dh_toml_loads_or_raises_a_scara_opt_error(data, tmp_path_factory):
    """Mutated DH TOML files (lines deleted, duplicated, garbage values, stray keys/tables).

    Mutation: dh._number without its finite-number check (a string, list or table where a
    number belongs raises ValueError/TypeError) -> fails.
    """
    source = data.draw(st.sampled_from(TOML_SOURCES))
    lines = source.read_text().splitlines()
    for _ in range(data.draw(st.integers(1, 3))):
        k = data.draw(st.integers(0, len(lines) - 1))
        kind = data.draw(st.sampled_from(["delete", "duplicate", "value", "insert"]))
        if kind == "delete":
            del lines[k]
        elif kind == "duplicate":
            lines.insert(k, lines[k])
        elif kind == "value" and "=" in lines[k]:
            key = lines[k].split("=", 1)[0]
            lines[k] = f"{key}= {data.draw(st.sampled_from(TOML_GARBAGE))}"
        else:
            lines.insert(k, data.draw(st.sampled_from(TOML_LINES)))
        if not lines:
            break
    path = tmp_path_factory.mktemp("toml") / "robot.toml"
    path.write_text("\n".join(lines))
    logging.disable(logging.WARNING)
    try:
        robot = so.load_robot(path)
        _check_loaded(robot)
    except so.ScaraOptError:
        return
    finally:
        logging.disable(logging.NOTSET)

