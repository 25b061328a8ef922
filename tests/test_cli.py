"""The scara-opt command line, driven as a user would."""

from __future__ import annotations

import subprocess
import sys

from tests.conftest import BUNDLED


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "scara_opt.cli", *args],
                          capture_output=True, text=True, timeout=120)


def test_robots_lists_every_bundled_robot_with_limits_and_source():
    """`scara-opt robots` exits 0 and names each robot, its joints' limits and its paper."""
    out = run("robots")
    assert out.returncode == 0, out.stderr
    for name in BUNDLED:
        assert name in out.stdout
    assert "[-120.0, 120.0] deg" in out.stdout and "seeds/" in out.stdout


def test_bad_usage_exits_2():
    """An unknown subcommand is a usage error: exit code 2, message on stderr."""
    out = run("no-such-command")
    assert out.returncode == 2 and "invalid choice" in out.stderr
