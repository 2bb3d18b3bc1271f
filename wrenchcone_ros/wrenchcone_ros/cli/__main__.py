"""``python -m wrenchcone_ros.cli``: the same as the ``wrenchcone`` command."""

import sys

from . import main

sys.exit(main())
