"""``python -m clap_unified``: the ``clap-unified`` command."""

import sys

from .cli import main

if __name__ == "__main__":  # not when imported (the doctest run imports every module)
    sys.exit(main())
