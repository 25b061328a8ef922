"""The project's promises about itself: README commands and CI stay in step."""

from __future__ import annotations

from tests.conftest import ROOT


def test_ci_runs_the_readme_commands():
    """.ci/run executes the README's first two commands verbatim (install + main job, tests)."""
    readme = (ROOT / "README.md").read_text()
    block = readme.split("```bash\n", 1)[1].split("```", 1)[0].strip().splitlines()
    assert len(block) >= 2
    ci = (ROOT / ".ci" / "run").read_text()
    for command in block[:2]:
        assert command in ci, f"README command not in .ci/run: {command}"
    assert "pytest" in block[1]


def test_readme_quickstart_runs():
    """The README's Python quickstart runs as printed and its results are what it claims."""
    readme = (ROOT / "README.md").read_text()
    code = readme.split("```python\n", 1)[1].split("```", 1)[0]
    scope: dict = {}
    exec(compile(code, "README quickstart", "exec"), scope)  # noqa: S102
    assert scope["res"].success and scope["ref"].success
    assert scope["batch"].success.all()
    assert all((r <= 1 + 1e-9).all() for r in scope["traj"].check_limits().values())
