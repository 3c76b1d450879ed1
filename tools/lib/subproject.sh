#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds tests/subproject/, a parent project that pulls stabdae in with add_subdirectory and
# then with FetchContent, where Check and SUNDIALS cannot be found: pkg-config sees only GSL's
# gsl.pc, and CMake's config-package search is re-rooted into an empty directory
# (CMAKE_FIND_ROOT_PATH_MODE_PACKAGE=ONLY), so no SUNDIALSConfig.cmake is found. Checks that
# - the configure fails as soon as stabdae is asked for its tests (Check) or its tools
#   (SUNDIALS): the hiding works;
# - with stabdae's defaults the configure succeeds without looking for Check, SUNDIALS or
#   Python (nothing in its output, no cache entry of theirs), leaves the parent's build type
#   and BUILD_SHARED_LIBS alone, and defines no test, example or tool target;
# - stabdae's warning, -Werror and no-vectorization flags are on stabdae's own sources and not
#   on the parent's;
# - the parent's programs link stabdae::stabdae (libstabdae.so.0 of this build) and
#   stabdae::stabdae_static (no libstabdae loaded), and both pass their checks.
# Usage: tools/lib/subproject.sh [BUILD_DIR]   (default build/)
set -euo pipefail
source "$(dirname "$0")/setup.sh"
build=${1:-$BUILD}
top=$build/subproject
rm -rf "$top"
mkdir -p "$top/pkgconfig" "$top/empty-root"

gsl_pc="$(pkg-config --variable=pcfiledir gsl)/gsl.pc"
[ -f "$gsl_pc" ] || { echo "subproject: no gsl.pc at $gsl_pc" >&2; exit 1; }
ln -s "$gsl_pc" "$top/pkgconfig/gsl.pc"

# parent_configure DIR VIA [cmake options...]: configure tests/subproject/ in the hiding
# environment; output in DIR.log
parent_configure() {
  local dir=$1 via=$2
  shift 2
  env -u PKG_CONFIG_PATH -u CMAKE_PREFIX_PATH -u SUNDIALS_DIR PKG_CONFIG_LIBDIR="$top/pkgconfig" \
    cmake -S "$ROOT/tests/subproject" -B "$dir" -DSTABDAE_SOURCE_DIR="$ROOT" \
    -DSTABDAE_VIA="$via" -DCMAKE_FIND_ROOT_PATH="$top/empty-root" \
    -DCMAKE_FIND_ROOT_PATH_MODE_PACKAGE=ONLY "$@" >"$dir.log" 2>&1
}

fail() {
  echo "subproject: $*" >&2
  exit 1
}

say "subproject: Check and SUNDIALS are out of reach"
PKG_CONFIG_LIBDIR="$top/pkgconfig" pkg-config --exists check &&
  fail "pkg-config still finds check.pc"
if parent_configure "$top/control-tests" add_subdirectory -DSTABDAE_BUILD_TESTS=ON; then
  fail "asked for its tests, stabdae configured without Check (log: $top/control-tests.log)"
fi
grep -q "'check'" "$top/control-tests.log" ||
  fail "the tests' configure failed, but not on Check: $(tail -n 5 "$top/control-tests.log")"
if parent_configure "$top/control-tools" add_subdirectory -DSTABDAE_BUILD_TOOLS=ON; then
  fail "asked for its tools, stabdae configured without SUNDIALS (log: $top/control-tools.log)"
fi
grep -q "SUNDIALS" "$top/control-tools.log" ||
  fail "the tools' configure failed, but not on SUNDIALS: $(tail -n 5 "$top/control-tools.log")"

for via in add_subdirectory fetchcontent; do
  dir=$top/$via
  say "subproject via $via"
  parent_configure "$dir" "$via" -DSTABDAE_WERROR=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON ||
    fail "configure failed: $(cat "$dir.log")"
  cache=$dir/CMakeCache.txt

  # nothing looked for but GSL
  unwanted_output="sundials|'check'|python|openmp"
  if grep -Eqi "$unwanted_output" "$dir.log"; then
    fail "the configure mentions what it should not look for: $(grep -Ei "$unwanted_output" \
      "$dir.log")"
  fi
  # what find_package and pkg_check_modules leave in the cache, found or not
  unwanted_cache='^(SUNDIALS_DIR|CHECK_[A-Z_]*|__pkg_config_checked_CHECK|Python3_[A-Z_]*'
  unwanted_cache+='|OpenMP_[A-Za-z_]*)[:=]'
  if grep -Eq "$unwanted_cache" "$cache"; then
    fail "Check, SUNDIALS, Python or OpenMP was looked for: $(grep -E "$unwanted_cache" "$cache")"
  fi
  for option in TESTS EXAMPLES TOOLS; do
    grep -qx "STABDAE_BUILD_$option:BOOL=OFF" "$cache" ||
      fail "STABDAE_BUILD_$option is not OFF in a subproject:" \
        "$(grep "STABDAE_BUILD_$option" "$cache")"
  done
  # the parent's own settings are left alone
  grep -qx 'CMAKE_BUILD_TYPE:STRING=' "$cache" ||
    fail "the parent's build type was changed: $(grep '^CMAKE_BUILD_TYPE' "$cache")"
  if grep -q '^BUILD_SHARED_LIBS' "$cache"; then
    fail "BUILD_SHARED_LIBS was put in the parent's cache"
  fi

  # no test, example or tool target
  targets=$(cmake --build "$dir" --target help | sed -n 's/^\.\.\. \([^ ]*\).*/\1/p')
  grep -q '^stabdae$' <<<"$targets" || fail "no stabdae target in the target list: $targets"
  unwanted_targets='^(check_|fuzz_|stabdae_testmodels|stabdae_example|test$|test_ida$|idaref$'
  unwanted_targets+='|ida_reference$|minimal$|oscillator$|pendulum$|chain$|bench$|workprecision$)'
  extra=$(grep -E "$unwanted_targets" <<<"$targets" || true)
  [ -z "$extra" ] || fail "targets of the tests, examples or tools: $(echo $extra)"

  cmake --build "$dir" -j "$JOBS" >"$dir.build.log" 2>&1 ||
    fail "build failed: $(tail -n 30 "$dir.build.log")"

  # stabdae's flags on its sources only
  commands=$dir/compile_commands.json
  own=$(grep '"command"' "$commands" | grep '/src/stepper/stepper\.c' || true)
  parent=$(grep '"command"' "$commands" | grep 'tests/subproject/subproject\.c' || true)
  [ -n "$own" ] && [ -n "$parent" ] || fail "compile commands missing in $commands"
  for flag in -Wall -Wextra -Werror; do
    grep -q -- "$flag" <<<"$own" || fail "stabdae's sources are built without $flag"
  done
  compiler=$(sed -n 's/^set(CMAKE_C_COMPILER_ID "\(.*\)")$/\1/p' \
    "$dir"/CMakeFiles/*/CMakeCCompiler.cmake)
  case $compiler in
    GNU) novec=-fno-tree-vectorize ;;
    Clang | AppleClang) novec=-fno-vectorize ;;
    *) novec= ;;
  esac
  if [ -n "$novec" ] && ! grep -q -- "$novec" <<<"$own"; then
    fail "stabdae's sources are built without $novec"
  fi
  for flag in -Wall -Wextra -Wpedantic -Werror -fno-tree-vectorize -fno-vectorize -fsanitize; do
    if grep -q -- "$flag" <<<"$parent"; then
      fail "stabdae's $flag leaked into the parent's compile command: $parent"
    fi
  done

  # the shared program loads this build's libstabdae.so.0, the static one none
  for flavour in shared static; do
    prog=$dir/parent_$flavour
    needed=$(readelf -d "$prog" | sed -n 's/.*Shared library: \[\(libstabdae[^]]*\)\].*/\1/p')
    loaded=$(ldd "$prog" | awk '/libstabdae/ {print $3}')
    if [ "$flavour" = static ]; then
      [ -z "$needed" ] || fail "parent_static needs $needed"
    else
      [ "$needed" = libstabdae.so.0 ] || fail "parent_shared needs '$needed'"
      [[ -n "$loaded" && "$(realpath "$loaded")" == "$(realpath "$dir")"/* ]] ||
        fail "parent_shared loads '$loaded', not the one built in $dir"
    fi
    "$prog"
  done
done
