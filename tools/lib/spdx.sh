#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Gives every tracked source file the licence's SPDX line as its first comment line (GPL-3.0 or
# later, the licence of LICENSE). A file that already has an SPDX line among its first three
# lines is left alone, so running this twice changes nothing. The lines:
#   C (.c, .h, .h.in):                   /* SPDX-License-Identifier: GPL-3.0-or-later */ as line 1
#   CMake, Python, shell (.cmake, .cmake.in, CMakeLists.txt, .py, .sh, and the executable
#   scripts without an extension that start with #!, such as tools/check):
#                                        # SPDX-License-Identifier: GPL-3.0-or-later
#     as line 1, or after the #! line and a Python coding line, which must stay first.
# Usage: tools/lib/spdx.sh           add the line where it is missing, list those files
#        tools/lib/spdx.sh --check   list the files without it; exit 1 if there is any
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
licence='SPDX-License-Identifier: GPL-3.0-or-later'

case ${1:-} in
  "") check=0 ;;
  --check) check=1 ;;
  *)
    echo "usage: tools/lib/spdx.sh [--check]" >&2
    exit 2
    ;;
esac
[ $# -le 1 ] || { echo "usage: tools/lib/spdx.sh [--check]" >&2; exit 2; }

# comment_style MODE PATH: "c", "hash", or nothing for a file that is not a source file
comment_style() {
  local mode=$1 path=$2 name
  name=$(basename "$path")
  case $name in
    *.c | *.h | *.h.in) echo c ;;
    *.py | *.sh | *.cmake | *.cmake.in | CMakeLists.txt) echo hash ;;
    *.*) ;;
    *) # an executable script without an extension (never a fuzz corpus input: not executable)
      if [ "$mode" = 100755 ] && [ "$(head -c 2 "$ROOT/$path")" = '#!' ]; then echo hash; fi ;;
  esac
}

# add_line STYLE FILE: writes the SPDX line into FILE in place (its mode is kept)
add_line() {
  local style=$1 file=$2 tmp
  tmp=$(mktemp)
  if [ "$style" = c ]; then
    { printf '/* %s */\n' "$licence"; cat "$file"; } >"$tmp"
  else
    awk -v line="# $licence" '
      !done && NR == 1 && /^#!/ { print; next }
      !done && NR <= 2 && /^[ \t\f]*#.*coding[:=][ \t]*[-_.a-zA-Z0-9]+/ { print; next }
      !done { print line; done = 1 }
      { print }
      END { if (!done) print line }' "$file" >"$tmp"
  fi
  cat "$tmp" >"$file"
  rm -f "$tmp"
}

missing=0
while IFS= read -r -d '' entry; do
  mode=${entry%% *}
  path=${entry#*$'\t'}
  file=$ROOT/$path
  [ -f "$file" ] && [ ! -L "$file" ] || continue
  # vendored files keep their own licence and bytes (third_party/*/README.md says whose)
  case $path in third_party/*) continue ;; esac
  style=$(comment_style "$mode" "$path")
  [ -n "$style" ] || continue
  if head -n 3 "$file" | grep -q 'SPDX-License-Identifier:'; then
    continue
  fi
  missing=$((missing + 1))
  if [ "$check" -eq 0 ]; then
    add_line "$style" "$file"
  fi
  echo "$path"
done < <(git -C "$ROOT" ls-files -s -z)

if [ "$check" -eq 1 ] && [ "$missing" -gt 0 ]; then
  echo "spdx: $missing tracked source files lack '$licence' (tools/lib/spdx.sh adds it)" >&2
  exit 1
fi
