"""``python -m ddes``: the ``ddes`` command, for when the script is not on ``PATH``."""

from __future__ import annotations

import sys

from ddes.cli.main import main

if __name__ == "__main__":
    sys.exit(main())
