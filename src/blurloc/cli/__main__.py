"""``python -m blurloc.cli``: the ``blurloc`` command."""

import sys

from . import main

sys.exit(main())
