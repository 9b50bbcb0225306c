"""Run the command line with ``python -m polyell``."""

import sys

from polyell.cli import main

sys.exit(main())
