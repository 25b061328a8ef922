r"""Griffe extension: the docstrings' Sphinx roles as mkdocstrings cross-references.

The package's docstrings link with Sphinx roles (``:class:`~scara_opt.Robot```,
``:func:`scara_opt.solve_ik```, ``:data:`MAX_BYTES```). This extension, loaded by
``mkdocs.yml``, rewrites each role before mkdocstrings renders the docstring:

- a dotted target that exists (imported and looked up) becomes an *optional* autoref: a link
  where the object has an API page, plain code where it has none;
- a dotted target that does **not** exist stays a plain autoref, which ``mkdocs build
  --strict`` reports as "Could not find cross-reference target": a broken docstring
  reference fails the build;
- an undotted or relative target (``:meth:`fk```, ``:mod:`.task```) becomes inline code;
- ``:math:`` becomes inline LaTeX ``\( ... \)`` and a ``.. math::`` block display LaTeX
  ``\[ ... \]``, which ``pymdownx.arithmatex`` (generic) hands to the KaTeX that
  ``mkdocs.yml`` loads (vendored under ``docs/javascripts``), as written: nothing stripped.

``~`` shows only the last name, as in Sphinx.
"""

from __future__ import annotations

import importlib
import re
from functools import cache
from typing import Any

try:
    from griffe import Extension
except ImportError:  # convert() and exists() work without griffe (the tests use them alone)
    Extension = object  # type: ignore[assignment,misc]

MATH = re.compile(r":math:`([^`]+)`")
ROLE = re.compile(r":(?:py:)?(class|func|meth|attr|data|mod|exc|obj):"
                  r"`(?:(?P<title>[^`<]+?)\s*<(?P<target2>[^`>]+)>|(?P<target>[^`]+))`")


@cache
def exists(path: str) -> bool:
    """True if ``path`` names a module, or an attribute reachable from one by getattr."""
    parts = path.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:i]))
        except (ImportError, TypeError, ValueError):
            continue
        for name in parts[i:]:
            if hasattr(obj, name):
                obj = getattr(obj, name)
                continue
            fields = getattr(obj, "__dataclass_fields__", {})
            doc = getattr(obj, "__doc__", "") or ""
            if name in fields or name in getattr(obj, "__annotations__", {}) or (
                    isinstance(obj, type) and re.search(rf"^\s+{re.escape(name)}:", doc, re.M)):
                obj = None  # an instance attribute the class documents
                continue
            return False
        return True
    return False


def convert(text: str, scope: str = "") -> str:
    """``text`` with every Sphinx role rewritten (see the module docstring).

    ``scope`` is the dotted path of the docstring's object: a target such as
    ``Robot.from_urdf`` is looked up in it and its parents, as Sphinx does.
    """
    parents = scope.split(".")
    scopes = [".".join(parents[:i]) for i in range(len(parents), 0, -1)] if scope else []

    def one(m: re.Match) -> str:
        title = m.group("title")
        target = (m.group("target2") or m.group("target")).strip()
        short = target.startswith("~")
        target = target.lstrip("~").rstrip("()")
        if "." not in target or target.startswith("."):
            return f"`{title or target}`"
        shown = title or (target.rsplit(".", 1)[-1] if short else target)
        for full in (target, *(f"{s}.{target}" for s in scopes)):
            if exists(full):
                return f'<autoref identifier="{full}" optional><code>{shown}</code></autoref>'
        return f"[`{shown}`][{target}]"

    text = MATH.sub(lambda m: "\\(" + m.group(1) + "\\)", text)
    return _math_blocks(ROLE.sub(one, text))


def _math_blocks(text: str) -> str:
    r"""Each ``.. math::`` directive as a display-math paragraph ``\[ ... \]`` of its LaTeX."""
    lines, out, k = text.split("\n"), [], 0
    while k < len(lines):
        line = lines[k]
        if line.strip() != ".. math::":
            out.append(line)
            k += 1
            continue
        indent = line[: len(line) - len(line.lstrip())]
        body, k = [], k + 1
        while k < len(lines) and (not lines[k].strip() or lines[k].startswith(indent + " ")):
            body.append(lines[k].strip())
            k += 1
        out += [f"{indent}\\[", *(f"{indent}{b}" for b in body if b), f"{indent}\\]", ""]
    return "\n".join(out)


class SphinxRoles(Extension):
    """Rewrite the Sphinx roles of every docstring griffe loads."""

    def on_instance(self, *, obj: Any, **kwargs: Any) -> None:
        """Griffe's hook, called for every object it loads."""
        if obj.docstring is not None:
            obj.docstring.value = convert(obj.docstring.value, obj.path)
