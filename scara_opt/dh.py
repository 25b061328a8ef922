"""Kept for compatibility: DH tables live in :mod:`scara_opt.model.dh` (re-exported here).

``python -m scara_opt.dh`` still regenerates every bundled URDF from its TOML.
"""

import sys

from scara_opt.model.dh import *  # noqa: F403  (re-exports)
from scara_opt.model.dh_file import *  # noqa: F403
from scara_opt.model.dh_file import main

if __name__ == "__main__":
    sys.exit(main())
