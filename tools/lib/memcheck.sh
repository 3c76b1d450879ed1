#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# valgrind memcheck of every Check suite, every fuzz corpus replay and the FMUs (through the
# FMI importer of fmi/tests) of a build: no error, no definite or indirect leak. CK_FORK=no
# keeps each test in valgrind's process. The alloc suite defines its own malloc (forwarding to
# __libc_malloc) to count allocations; valgrind would replace it too and bypass the count, so
# user-defined allocators are left alone (somalloc=nouserintercepts): valgrind still sees every
# block through __libc_malloc, and the suite's sweeps fail every malloc of the library in turn
# under memcheck (the suite says "not checked" when its malloc was bypassed: that fails the
# run). A summary line per program; the full logs are in BUILD/memcheck/.
# Usage: tools/lib/memcheck.sh [BUILD_DIR]   (default build/)
set -euo pipefail
source "$(dirname "$0")/setup.sh"
build=${1:-$BUILD}
logs=$build/memcheck
mkdir -p "$logs"

# memcheck PROGRAM [ARGS...]
memcheck() {
  local name log
  name=$(basename "$1")
  log=$logs/$name.log
  if ! CK_FORK=no valgrind --error-exitcode=99 --soname-synonyms=somalloc=nouserintercepts \
    --leak-check=full \
    --errors-for-leak-kinds=definite,indirect --show-leak-kinds=definite,indirect \
    --log-file="$log" "$@" >"$logs/$name.out" 2>&1; then
    cat "$logs/$name.out" "$log" >&2
    echo "memcheck: $name failed (log in ${log#"$ROOT"/})" >&2
    return 1
  fi
  if grep -q 'not checked' "$logs/$name.out"; then
    cat "$logs/$name.out" >&2
    echo "memcheck: $name skipped checks under valgrind" >&2
    return 1
  fi
  printf '%-22s %s; %s\n' "$name" \
    "$(sed -n 's/.*ERROR SUMMARY: \([0-9,]* errors\).*/\1/p' "$log")" \
    "$(sed -n 's/.*total heap usage: \(.*\)/\1/p' "$log")"
}

say "valgrind memcheck of the unit suites and the fuzz corpora"
for prog in "$build"/tests/check_*; do
  [ -f "$prog" ] && [ -x "$prog" ] && memcheck "$prog"
done
for prog in "$build"/tests/fuzz/fuzz_*; do
  [ -f "$prog" ] && [ -x "$prog" ] || continue
  name=$(basename "$prog")
  memcheck "$prog" "$ROOT/tests/fuzz/corpus/${name#fuzz_}"
done
# the FMUs' binaries loaded by our own importer (fmi/tests/importer.c), FMI 3.0 and 2.0: bad
# input, steps, roll-back, a failing step, reset and free
if [ -x "$build/fmi/tests/fmi_importer" ]; then
  for name in fourbar slider_crank; do
    for version in 3 2; do
      memcheck "$build/fmi/tests/fmi_importer" "$version" \
        "$build/examples/fmus/${name}_fmu/fmi$version" "$name"
    done
  done
fi
