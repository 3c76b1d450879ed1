#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The shared library exports the public API and nothing else: every defined symbol of its
# dynamic symbol table is a function or object declared in the public headers (so it starts
# with sdae_), and every one the headers declare is exported (so none lacks SDAE_API), but the
# ones the user defines: sdae_fmu_model, the table an FMU's own file defines (<stabdae/fmu.h>).
# Usage: check_exports.sh LIBRARY.so INCLUDE_DIR
set -euo pipefail
lib=$1 include=$2

exported=$(nm -D --defined-only "$lib" | awk 'NF >= 3 {print $3}' | sort -u)
# Declarations at file scope: prototypes "... sdae_name(" and "extern ... sdae_name;".
declared=$(cat "$include"/*.h | grep -E '^[A-Za-z_]' | grep -vE '^(typedef|#)' |
  sed -nE 's/^[^(]*\b(sdae_[a-z0-9_]+)\(.*/\1/p; s/^.*\bextern\b.*\b(sdae_[a-z0-9_]+);.*/\1/p' |
  grep -vx sdae_fmu_model | sort -u)

fail=0
if ! grep -qx sdae_step <<<"$exported"; then
  echo "sdae_step is not in the dynamic symbol table of $lib" >&2
  fail=1
fi
if ! grep -qx sdae_step <<<"$declared"; then
  echo "sdae_step is not declared in $include: the header scan is broken" >&2
  fail=1
fi
extra=$(comm -23 <(echo "$exported") <(echo "$declared"))
missing=$(comm -13 <(echo "$exported") <(echo "$declared"))
if [ -n "$extra" ]; then
  echo "exported but not public API:" $extra >&2
  fail=1
fi
if [ -n "$missing" ]; then
  echo "declared in the public headers but not exported (SDAE_API missing?):" $missing >&2
  fail=1
fi
[ "$fail" -eq 0 ] || exit 1
echo "$(wc -l <<<"$exported") symbols exported, each declared in $include"
