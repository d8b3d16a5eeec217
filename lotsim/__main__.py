"""``python -m lotsim`` runs the command-line interface."""

import sys

from lotsim.cli import main

sys.exit(main())
