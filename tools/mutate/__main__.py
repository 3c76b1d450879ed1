# SPDX-License-Identifier: GPL-3.0-or-later
"""python -m mutate (tools/mutate/mutate is its launcher)."""

import sys

from mutate.main import main

sys.exit(main())
