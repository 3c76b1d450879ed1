# SPDX-License-Identifier: GPL-3.0-or-later
"""python -m layers (tools/layers/layers is its launcher)."""

import sys

from layers.main import main

sys.exit(main())
