"""The [citation] table of robot files: full references, unstated fields said so, checked."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

import scara_opt as so
from scara_opt.model.citation import CITATION_FIELDS, check_citation, format_citation
from scara_opt.model.dh import FILE_KEYS
from scara_opt.model.dh_file import bundled_dir, load_dh
from tests.conftest import BUNDLED, ROOT

SEEDS = Path("/work/shared/seeds")
#: the text of each bundled robot's paper (in the project's shared folder, not in the repo)
TEXTS = {"zavar2024": "000_db41312e9a45ac0e.txt", "peng2025": "001_b35f9d7865ac69db.txt",
         "nguyen": "002_e63e44ba374820ad.txt", "inverted5": "003_923abea74416c111.txt",
         "fang": "004_bf70fd1cc4e521c8.txt"}


@pytest.mark.parametrize("name", BUNDLED)
def test_every_bundled_robot_cites_its_paper_and_the_robot_keeps_it(name):
    """Each bundled file has a valid [citation]; load_robot keeps it in metadata.

    Mutation caught: FILE_KEYS without "citation" (every bundled file refused).
    """
    robot = so.load_robot(name)
    table = robot.metadata["citation"]
    assert check_citation(table, name) is table
    for field in CITATION_FIELDS:
        assert (field in table) != (field in table.get("not_stated", []))


@pytest.mark.skipif(not SEEDS.is_dir(), reason="the papers' texts are not in this checkout")
@pytest.mark.parametrize("name", BUNDLED)
def test_what_a_citation_states_is_in_the_paper_text(name):
    """Authors, title, year and DOI of a citation appear in the paper's own text: none invented."""
    text = re.sub(r"\s+", " ", (SEEDS / TEXTS[name]).read_text())
    table = so.load_robot(name).metadata["citation"]
    for author in table.get("authors", []):
        assert author in text
    if "title" in table:
        assert table["title"].lower() in text.lower()
    if "year" in table:
        assert str(table["year"]) in text
    if "doi" in table:
        assert table["doi"] in text


def _file(tmp_path, citation: str) -> Path:
    src = (bundled_dir() / "zavar2024.toml").read_text().split("\n[citation]")[0]
    path = tmp_path / "r.toml"
    path.write_text(src + "\n[citation]\n" + citation)
    return path


@pytest.mark.parametrize("citation, match", [
    ('authors = ["A"]\ntitle = "T"\nyear = 2020\nnot_stated = ["venue"]\n',
     "doi is neither given nor in not_stated"),
    ('authors = ["A"]\ntitle = "T"\nyear = 2020\ndoi = "10.1000/x"\n'
     'not_stated = ["venue", "doi"]\n', "doi is both given and listed"),
    ('authors = "A"\ntitle = "T"\nnot_stated = ["venue", "year", "doi"]\n', "list of names"),
    ('authors = ["A"]\ntitle = "T"\nyear = 20\nnot_stated = ["venue", "doi"]\n',
     "year must be an integer"),
    ('authors = ["A"]\ntitle = "T"\nyear = 2020\nvenue = "V"\n'
     'doi = "https://doi.org/10.1000/x"\n', "doi must look like"),
    ('authors = ["A"]\ntitel = "T"\nnot_stated = ["venue", "year", "doi"]\n',
     "unknown key"),
    ('not_stated = ["authors", "title", "venue", "year", "doi", "isbn"]\n', "not_stated must"),
])
def test_incomplete_or_malformed_citations_are_refused(tmp_path, citation, match):
    """A field neither given nor listed as not stated, a bad DOI or year: URDFError.

    Mutation caught: the given == listed check removed (a forgotten DOI passes).
    """
    with pytest.raises(so.URDFError, match=match):
        load_dh(_file(tmp_path, citation))


def test_a_full_citation_formats_on_one_line(tmp_path):
    """A complete reference: authors (year). “title”. venue. doi:…"""
    table = {"authors": ["A. One", "B. Two"], "title": "T", "venue": "J. Rob.", "year": 2020,
             "doi": "10.1000/xyz"}
    assert load_dh(_file(tmp_path, "".join(f"{k} = {v!r}\n".replace("'", '"')
                                           for k, v in table.items())))
    assert format_citation(table) == "A. One, B. Two (2020). “T”. J. Rob. doi:10.1000/xyz."


def test_readme_and_robots_readme_give_every_reference_and_table():
    """The README lists each paper's reference; robots/README.md documents every file table."""
    readme = (ROOT / "README.md").read_text()
    for name in BUNDLED:
        table = tomllib.loads((bundled_dir() / f"{name}.toml").read_text())["citation"]
        if "title" in table:
            assert table["title"] in readme
    guide = (ROOT / "robots" / "README.md").read_text()
    for key in FILE_KEYS:
        assert any(f"`{k}`" in guide for k in (key, f"[{key}]", f"[[{key}]]")), key
    for table in ("[[joints]]", "[tool]", "[footprint]", "[citation]"):
        assert f"`{table}`" in guide


def test_every_example_says_what_it_needs_up_front():
    """Each example's docstring says, right after its title, what it needs beyond the base
    install, naming every extra of its PEP 723 ``dependencies`` (panda.py: ``robots``).

    Mutation caught: panda.py's Needs line saying "the base install only".
    """
    import ast

    for path in sorted((ROOT / "examples").glob("*.py")):
        text = path.read_text()
        deps = re.search(r"^# dependencies = \[(.*)\]$", text, re.M).group(1)
        extras = re.findall(r"scara-opt\[(\w+)\]", deps)
        doc = ast.get_docstring(ast.parse(text))
        needs = doc.split("\n\n")[1]
        assert needs.startswith("Needs:"), path.name
        if extras:
            for extra in extras:
                assert f'pip install "scara-opt[{extra}]"' in needs, path.name
        else:
            assert "base install only" in needs, path.name
