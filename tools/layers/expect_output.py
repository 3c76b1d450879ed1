# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs a command and passes only when its exit status and its whole standard output are the
expected ones: a checker shown to fail must fail for exactly the planted reasons, not for one
more or one less.

Usage: python3 -m layers.expect_output STATUS EXPECTED_FILE -- COMMAND [ARG...]
"""

import difflib
import subprocess
import sys


def main(argv):
    if len(argv) < 4 or argv[2] != '--':
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    status, expected_file, command = int(argv[0]), argv[1], argv[3:]
    run = subprocess.run(command, capture_output=True, text=True, check=False)
    with open(expected_file, encoding='utf-8') as f:
        expected = f.read().splitlines()
    got = run.stdout.splitlines()
    ok = True
    if run.returncode != status:
        print(f'exit status {run.returncode}, expected {status}')
        ok = False
    if got != expected:
        print('standard output differs from ' + expected_file + ':')
        sys.stdout.writelines(
            line + '\n'
            for line in difflib.unified_diff(expected, got, 'expected', 'got', lineterm='')
        )
        ok = False
    if run.stderr:
        print('standard error:\n' + run.stderr, end='')
    if ok:
        print(f'as expected (exit status {status}):')
        print(run.stdout, end='')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
