"""``python -m forcelayout``: the ``forcelayout`` command line."""

import sys

from forcelayout.cli import main

sys.exit(main())
