"""``python -m scara_opt.cli``: the command line, ending exactly as the ``scara-opt`` script."""

from scara_opt.cli.console import main

main()
