"""``python -m windpump``: the ``windpump`` command (:mod:`windpump.command.cli`)."""

import sys

from .command.cli import main

sys.exit(main())
