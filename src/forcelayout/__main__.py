"""``python -m forcelayout``: the ``forcelayout`` command line."""

import sys

from forcelayout.cli import main

if __name__ == "__main__":
    sys.exit(main())
