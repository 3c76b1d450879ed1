# SPDX-License-Identifier: GPL-3.0-or-later
"""python -m stabdae_ref MODEL [options]: a run as CSV (cli.py); python -m stabdae_ref expected
[--outdir DIR]: the answers of the C examples' regression tests (expected.py). The one entry
of the package: neither module imports this one.

Bad input: one line on stderr, exit 2, no output file. A step that fails: the rows computed so
far stay written, one line on stderr says where it stopped, exit 1.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from . import cli, expected


def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["expected"]:
        return expected.main(argv[1:])
    return cli.main(argv)


if __name__ == "__main__":
    sys.exit(main())
