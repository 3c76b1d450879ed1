#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the built tree into BUILD/prefix and builds tests/consumer against it four ways:
# find_package(stabdae) with the shared library, find_package with stabdae::stabdae_static,
# pkg-config, and pkg-config --static with libstabdae.a; runs each and checks which library it
# loads. With the FMI layer built, an FMU
# of a mechanism of its own too (tests/consumer_fmu, stabdae_add_fmu after find_package).
# Usage: tools/lib/consumer.sh [BUILD_DIR]   (default build/)
set -euo pipefail
source "$(dirname "$0")/setup.sh"
build=${1:-$BUILD}
prefix=$build/prefix

say "installing into ${prefix#"$ROOT"/}"
rm -rf "$prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
pcdir=$(dirname "$(find "$prefix" -name stabdae.pc | head -n 1)")

for via in cmake cmake-static pkg-config pkg-config-static; do
  dir=$build/consumer/$via
  say "consumer via $via"
  rm -rf "$dir"
  PKG_CONFIG_PATH="$pcdir" cmake -S "$ROOT/tests/consumer" -B "$dir" -DSTABDAE_VIA="$via" \
    -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
  cmake --build "$dir" >/dev/null
  # the shared builds must load the installed libstabdae.so.0, the static one none
  needed=$(readelf -d "$dir/consumer" | sed -n 's/.*Shared library: \[\(libstabdae[^]]*\)\].*/\1/p')
  loaded=$(ldd "$dir/consumer" | awk '/libstabdae/ {print $3}')
  if [[ "$via" == *-static ]]; then
    [ -z "$needed" ] || { echo "static consumer needs $needed" >&2; exit 1; }
  else
    [ "$needed" = libstabdae.so.0 ] || { echo "consumer needs '$needed'" >&2; exit 1; }
    [[ -n "$loaded" && "$(realpath "$loaded")" == "$(realpath "$prefix")"/* ]] ||
      { echo "consumer loads '$loaded', not the one in $prefix" >&2; exit 1; }
  fi
  "$dir/consumer"
done

# an FMU of the user's own mechanism (tests/consumer_fmu: a mechanism in the generator's shape,
# its table, one stabdae_add_fmu line) built against the install, when stabdae was built with
# its FMI layer; the FMI importer of fmi/tests then runs each version of it unpacked
if [ -n "$(find "$prefix" -name StabdaeFmu.cmake -print -quit)" ]; then
  dir=$build/consumer/fmu
  say "consumer FMU via stabdae_add_fmu"
  rm -rf "$dir"
  cmake -S "$ROOT/tests/consumer_fmu" -B "$dir" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
  cmake --build "$dir" >/dev/null
  for version in 3 2; do
    fmu=$dir/fmi$version/pendulum.fmu
    unpacked=$dir/unpacked$version
    mkdir -p "$unpacked"
    (cd "$unpacked" && cmake -E tar xf "$fmu")
    if [ -x "$build/fmi/tests/fmi_importer" ]; then
      "$build/fmi/tests/fmi_importer" "$version" "$unpacked" pendulum
    else
      [ -f "$unpacked/modelDescription.xml" ] || { echo "$fmu: no modelDescription.xml" >&2; exit 1; }
    fi
  done
fi
