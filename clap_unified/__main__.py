"""``python -m clap_unified``: the ``clap-unified`` command."""

import sys

from .cli import main

sys.exit(main())
