"""``python -m navlab``: the command line (``navlab.cli``), with the CPU code paths pinned first.

The pins (``navlab.core.cpu``) must be in the environment before torch, OpenCV or NumPy load, and before
the notebook kernels and worker processes a command starts inherit it; importing ``navlab.cli`` loads them.
"""

from navlab.core.cpu import pin_code_paths

pin_code_paths()

from navlab.cli import main  # after the pins, on purpose

raise SystemExit(main())
