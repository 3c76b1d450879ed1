# SPDX-License-Identifier: GPL-3.0-or-later
# The one entry of the Python tools (sourced by each tool's launcher): the tool is a package of
# tools/, run as `python -m PACKAGE` with tools/ on PYTHONPATH. The Python is $PYTHON when set,
# else the harness's venv (build/venv, made by tools/check and tools/demo) when it exists, else
# python3.

# launch PACKAGE [ARGUMENTS...]: replaces the shell with the package's run
launch() {
  local package=$1 tools python
  shift
  tools=$(CDPATH='' cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  python=${PYTHON:-}
  if [ -z "$python" ]; then
    python=python3
    [ -x "$tools/../build/venv/bin/python" ] && python=$tools/../build/venv/bin/python
  fi
  # -P (Python 3.11 on): the current folder off sys.path, so that a module there (say
  # tools/benchmarks/benchmarks.py, run from that folder) does not stand for the package
  local safe=()
  "$python" -P -c '' 2>/dev/null && safe=(-P)
  PYTHONPATH="$tools${PYTHONPATH:+:$PYTHONPATH}" exec "$python" "${safe[@]}" -m "$package" "$@"
}
