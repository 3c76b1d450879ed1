# SPDX-License-Identifier: GPL-3.0-or-later
"""python -m stabdae_gen MODEL.py --out DIR: the command behind tools/mbsgen."""

import sys

from .cli import main

sys.exit(main(sys.argv[1:]))
