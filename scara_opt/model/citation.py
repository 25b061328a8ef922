"""The ``[citation]`` table of a robot file: the paper a robot comes from, as a full reference.

Five fields make a reference: ``authors`` (list of names), ``title``, ``venue`` (journal or
conference), ``year`` and ``doi``. A robot file gives each one it knows, and lists the
ones its source does not state under ``not_stated``: every field is either given or listed,
never both, so a missing DOI is a stated fact, not a forgotten line. Optional:
``affiliation`` and ``note`` (free text, e.g. where a year comes from)::

    [citation]
    authors = ["Mahdi Zavar", "Niki Manouchehri", "Alireza Safa"]
    title = "Forward and Inverse Kinematics of 4-DoF SCARA: Using Optimization Algorithms"
    year = 2024
    not_stated = ["venue", "doi"]

:func:`check_citation` is called by the robot-file reader; the table is kept in
:attr:`Robot.metadata["citation"] <scara_opt.Robot.metadata>`; :func:`format_citation`
writes it as one line (``scara-opt robots``).
"""

from __future__ import annotations

import re

from scara_opt.errors import URDFError

#: the fields of a full reference: each given, or named in ``not_stated``
CITATION_FIELDS = ("authors", "title", "venue", "year", "doi")
#: every key a ``[citation]`` table may have
CITATION_KEYS = (*CITATION_FIELDS, "not_stated", "affiliation", "note")
#: a DOI as the DOI Handbook writes it: ``10.<registrant>/<suffix>``, no URL prefix
DOI_PATTERN = re.compile(r"^10\.\d{4,9}/\S+$")
#: years a paper on these robots can have
YEAR_RANGE = (1950, 2100)

__all__ = ["CITATION_FIELDS", "CITATION_KEYS", "check_citation", "format_citation"]


def _is_text(value: object) -> bool:
    return isinstance(value, str) and value.strip() != ""


def check_citation(table: object, where: str) -> dict:
    """``table`` if it is a valid ``[citation]`` table (see the module docstring).

    Raises:
        URDFError: not a table; an unknown key; a field neither given nor in ``not_stated``
            (or both); ``authors`` not a list of names; an empty title, venue or note; a
            year outside :data:`YEAR_RANGE`; a DOI not of the form ``10.NNNN/suffix``.
    """
    at = f"{where}: [citation]"
    if not isinstance(table, dict):
        raise URDFError(f"{at} must be a TOML table (key = value lines), got {table!r}")
    unknown = [k for k in table if k not in CITATION_KEYS]
    if unknown:
        raise URDFError(f"{at} has unknown key(s) {', '.join(map(repr, unknown))}; accepted "
                        f"keys: {', '.join(CITATION_KEYS)}")
    missing = table.get("not_stated", [])
    if not (isinstance(missing, list) and all(m in CITATION_FIELDS for m in missing)
            and len(set(missing)) == len(missing)):
        raise URDFError(f"{at}: not_stated must list fields among {', '.join(CITATION_FIELDS)}, "
                        f"each once; got {missing!r}")
    for name in CITATION_FIELDS:
        given, listed = name in table, name in missing
        if given == listed:
            raise URDFError(
                f"{at}: {name} is {'both given and listed' if given else 'neither given nor'} "
                f"in not_stated; give the {name} the paper states, or add {name!r} to "
                "not_stated if it states none")
    authors = table.get("authors", ["-"])
    if not (isinstance(authors, list) and authors and all(map(_is_text, authors))):
        raise URDFError(f"{at}: authors must be a list of names, e.g. [\"A. Author\", "
                        f"\"B. Author\"]; got {authors!r}")
    for name in ("title", "venue", "affiliation", "note"):
        if name in table and not _is_text(table[name]):
            raise URDFError(f"{at}: {name} must be a non-empty string, got {table[name]!r}")
    year = table.get("year", YEAR_RANGE[0])
    if not (isinstance(year, int) and not isinstance(year, bool)
            and YEAR_RANGE[0] <= year <= YEAR_RANGE[1]):
        raise URDFError(f"{at}: year must be an integer in {list(YEAR_RANGE)}, got {year!r}")
    doi = table.get("doi", "10.0000/x")
    if not (isinstance(doi, str) and DOI_PATTERN.match(doi)):
        raise URDFError(f"{at}: doi must look like 10.NNNN/suffix (no https://doi.org/ "
                        f"prefix), got {doi!r}")
    return table


def format_citation(table: dict) -> str:
    """One line: ``Authors (year). “Title”. Venue. doi:…`` then the fields not stated.

    E.g. ``Mahdi Zavar, … (2024). “Forward and …”. Not stated in the paper's text: venue, doi.``
    """
    head = ", ".join(table.get("authors", []))
    if "year" in table:
        head += f" ({table['year']})" if head else f"({table['year']})"
    parts = [head] if head else []
    if "title" in table:
        parts.append(f"“{table['title']}”")
    if "venue" in table:
        parts.append(table["venue"])
    if "doi" in table:
        parts.append(f"doi:{table['doi']}")
    missing = [f for f in CITATION_FIELDS if f in table.get("not_stated", [])]
    if missing:
        parts.append(f"Not stated in the paper's text: {', '.join(missing)}")
    return ". ".join(p.rstrip(".") for p in parts) + "."
