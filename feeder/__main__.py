"""``python -m feeder`` and the ``feeder`` command: the command line of :mod:`feeder.cli`."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
