"""``python -m cablecasing_core``: the command line (as ``cablecasing``)."""

import sys

from .cli import main

sys.exit(main())
