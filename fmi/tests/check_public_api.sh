#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The FMI layer uses stabdae's public API only: every sdae_ symbol its static libraries call is
# one the shared library exports (its public API, ctest exports.only_public_api), but
# sdae_fmu_model, the table the FMU's own file defines.
# Usage: check_public_api.sh LIBSTABDAE.so LIBRARY.a...
set -euo pipefail
lib=$1
shift
exported=$(nm -D --defined-only "$lib" | awk 'NF >= 3 {print $3}' | sort -u)
used=$(nm -u "$@" | awk '$1 == "U" && $2 ~ /^sdae_/ {print $2}' | grep -vx sdae_fmu_model | sort -u)
[ -n "$used" ] || { echo "no sdae_ symbol used by $*: the scan is broken" >&2; exit 1; }
outside=$(comm -23 <(echo "$used") <(echo "$exported"))
if [ -n "$outside" ]; then
  echo "the FMI layer calls what is not public API:" $outside >&2
  exit 1
fi
echo "$(wc -l <<<"$used") sdae_ symbols used, each public API"
