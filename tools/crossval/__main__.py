# SPDX-License-Identifier: GPL-3.0-or-later
"""python -m crossval (tools/crossval/crossval is its launcher)."""

import sys

from crossval.main import main

sys.exit(main())
