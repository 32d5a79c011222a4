"""``python -m windpump``: the ``windpump`` command (:mod:`windpump.cli`)."""

import sys

from .cli import main

sys.exit(main())
