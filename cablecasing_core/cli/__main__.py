"""``python -m cablecasing_core.cli``: the command line (as ``cablecasing``)."""

import sys

from . import main

sys.exit(main())
