#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# tools/cross/cross cortex-m7: stabdae on a bare-metal Cortex-M7 with its double-precision FPU,
# run on QEMU's mps2-an500 board with output by semihosting (docs/embedded.md).
#   1. GSL and SuiteSparse for the target, from Debian's source packages (their orig tarballs,
#      checked against the digests below, in build/cross/src): GSL configured for arm-none-eabi
#      and the folders the library and the example mechanisms call built (fused multiply-adds
#      off, as the library compiles), AMD, LDL and SuiteSparse_config compiled as the library
#      links them (SuiteSparse_long indices: a 32-bit long here); both into
#      build/cross/cortex-m7/sysroot
#   2. tools/cross/cortex-m7/ with cmake/toolchains/cortex-m7.cmake: the library, the paper's
#      oscillator (examples/minimal.c), the four-bar (examples/fourbar_minimal.c) and the probe
#   3. each run on the board; the two tables must equal the host's (the same sources built for
#      the host in build/) to every printed digit; the probe's table (block, stack, heap)
#   4. build/cross/cortex-m7/report.md: those, the footprint of each program by origin (its
#      linker map) and the largest stack frames of the library (-fstack-usage)
# Exit status: 0; 1 when a build fails, a table differs, a run fails, the probe finds heap use
# after set-up or a download has not the digest below; 2 for a missing package (one line naming
# it) or a download that cannot be had.
set -euo pipefail
source "$(dirname "$0")/../lib/setup.sh"

GSL_TAR=gsl_2.7.1+dfsg.orig.tar.gz
GSL_SHA256=e560d6b9c6e254e46769bbb03583c00ecafbdd51b062c55db23b3b9612868567
SS_TAR=suitesparse_5.12.0+dfsg.orig.tar.xz
SS_SHA256=bb106c43049138c19675cd70322e72ff8e4fd8bdcab3a096307fd78488913faf
POOL=http://deb.debian.org/debian/pool/main
# GSL's folders the library (linalg, permutation, matrix and vector views, rng) and the example
# mechanisms (specfunc: the pendulum's elliptic functions) need, with what they call
GSL_DIRS="utils sys err ieee-utils block vector matrix permutation blas linalg rng complex specfunc"
FLAGS="-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb -ffunction-sections -fdata-sections"
QEMU=(qemu-system-arm -M mps2-an500 -nographic -monitor none -semihosting -kernel)

dir="$BUILD/cross/cortex-m7"
src="$BUILD/cross/src"
sysroot="$dir/sysroot"

missing() {
  local pkgs=()
  command -v arm-none-eabi-gcc >/dev/null || pkgs+=(gcc-arm-none-eabi)
  [ -e /usr/lib/arm-none-eabi/newlib/thumb/v7e-m+dp/hard/librdimon.a ] ||
    pkgs+=(libnewlib-arm-none-eabi)
  command -v qemu-system-arm >/dev/null || pkgs+=(qemu-system-arm)
  command -v curl >/dev/null || pkgs+=(curl)
  command -v xz >/dev/null || pkgs+=(xz-utils)
  echo "${pkgs[@]}"
}
ensure_packages # the host's compiler, cmake, make and libraries, for the host's two programs
pkgs=$(missing)
if [ -n "$pkgs" ]; then
  if [ "$(id -u)" -ne 0 ] || ! command -v apt-get >/dev/null; then
    echo "cross: missing Debian packages: $pkgs (apt-get install)" >&2
    exit 2
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq || { sleep 10 && apt-get update -qq; } || true
  say "installing for cortex-m7: $pkgs"
  # shellcheck disable=SC2086
  apt-get install -y -qq --no-install-recommends $pkgs >/dev/null ||
    { echo "cross: could not install $pkgs (apt-get failed; see above)" >&2; exit 2; }
fi

# fetch TARBALL SHA256 PACKAGE: Debian's orig tarball into build/cross/src, kept once checked
fetch() {
  local tar=$1 sum=$2 package=$3
  mkdir -p "$src"
  if ! echo "$sum  $src/$tar" | sha256sum -c --quiet >/dev/null 2>&1; then
    say "downloading $tar (Debian's source of $package)"
    curl -sSf -o "$src/$tar.part" "$POOL/${package:0:1}/$package/$tar" ||
      { echo "cross: cannot download $POOL/${package:0:1}/$package/$tar" >&2; exit 2; }
    echo "$sum  $src/$tar.part" | sha256sum -c --quiet >/dev/null 2>&1 ||
      { echo "cross: $tar does not have the expected SHA-256" >&2; exit 1; }
    mv "$src/$tar.part" "$src/$tar"
  fi
}

# GSL's folders for the target, merged into one libgsl.a (objects renamed by folder: several
# folders have an init.o), libgslcblas.a apart, every gsl_*.h into include/gsl
build_gsl() {
  local gsl="$src/gsl" out="$dir/gsl" d o
  [ -d "$gsl" ] || tar -xzf "$src/$GSL_TAR" -C "$src"
  rm -rf "$out" && mkdir -p "$out/objects" "$sysroot/lib" "$sysroot/include/gsl"
  say "GSL for the Cortex-M7 (configure, then $GSL_DIRS cblas)"
  (cd "$out" && "$gsl/configure" --host=arm-none-eabi --disable-shared --enable-static \
    CFLAGS="-O2 -ffp-contract=off $FLAGS" LDFLAGS=--specs=nosys.specs >configure.log 2>&1 &&
    make -C gsl >make.log 2>&1 &&
    for d in $GSL_DIRS cblas; do make -C "$d" -j "$JOBS" >>make.log 2>&1 || exit 1; done) ||
    { echo "cross: GSL did not build for the target (see $out/configure.log, make.log)" >&2
      exit 1; }
  for d in $GSL_DIRS; do
    mkdir -p "$out/x" && (cd "$out/x" && arm-none-eabi-ar x "$out/$d"/.libs/*.a &&
      for o in *.o; do mv "$o" "$out/objects/${d}_$o"; done)
  done
  rm -f "$sysroot/lib/libgsl.a"
  arm-none-eabi-ar rcs "$sysroot/lib/libgsl.a" "$out"/objects/*.o
  cp "$out/cblas/.libs/libgslcblas.a" "$sysroot/lib/"
  find "$gsl" -name 'gsl_*.h' -exec cp {} "$sysroot/include/gsl/" \;
}

# AMD (its SuiteSparse_long functions, -DDLONG), LDL (-DLDL_LONG) and SuiteSparse_config (no
# timer: no clock_gettime on bare metal), as the library calls them; SuiteSparse_long is a
# 32-bit long here, which sdae__sparse_ldl_fits bounds the sizes for
build_suitesparse() {
  local ss="$src/SuiteSparse-5.12.0" out="$dir/suitesparse" f
  [ -d "$ss" ] || tar -xJf "$src/$SS_TAR" -C "$src" SuiteSparse-5.12.0/AMD \
    SuiteSparse-5.12.0/LDL SuiteSparse-5.12.0/SuiteSparse_config
  rm -rf "$out" && mkdir -p "$out" "$sysroot/lib" "$sysroot/include/suitesparse"
  say "SuiteSparse's AMD and LDL for the Cortex-M7"
  local cc=(arm-none-eabi-gcc -O2 -ffp-contract=off $FLAGS -I"$ss/SuiteSparse_config"
    -I"$ss/AMD/Include" -I"$ss/LDL/Include")
  for f in "$ss"/AMD/Source/amd_*.c; do
    "${cc[@]}" -DDLONG -c "$f" -o "$out/l_$(basename "$f" .c).o"
  done
  "${cc[@]}" -DLDL_LONG -c "$ss/LDL/Source/ldl.c" -o "$out/ldl_l.o"
  "${cc[@]}" -DNTIMER -c "$ss/SuiteSparse_config/SuiteSparse_config.c" -o "$out/config.o"
  rm -f "$sysroot"/lib/lib{amd,ldl,suitesparseconfig}.a
  arm-none-eabi-ar rcs "$sysroot/lib/libamd.a" "$out"/l_amd_*.o
  arm-none-eabi-ar rcs "$sysroot/lib/libldl.a" "$out/ldl_l.o"
  arm-none-eabi-ar rcs "$sysroot/lib/libsuitesparseconfig.a" "$out/config.o"
  cp "$ss/AMD/Include/amd.h" "$ss/LDL/Include/ldl.h" "$ss/SuiteSparse_config/SuiteSparse_config.h" \
    "$sysroot/include/suitesparse/"
}

# the sysroot is rebuilt when this script changes (its recipe)
stamp="$sysroot/.recipe"
if ! cmp -s "${BASH_SOURCE[0]}" "$stamp"; then
  fetch "$GSL_TAR" "$GSL_SHA256" gsl
  fetch "$SS_TAR" "$SS_SHA256" suitesparse
  rm -rf "$sysroot"
  build_gsl
  build_suitesparse
  cp "${BASH_SOURCE[0]}" "$stamp"
fi

say "the library and the programs for the Cortex-M7 (build/cross/cortex-m7/build)"
cmake -S "$ROOT/tools/cross/cortex-m7" -B "$dir/build" --no-warn-unused-cli \
  -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/toolchains/cortex-m7.cmake" \
  -DSTABDAE_M7_SYSROOT="$sysroot" -DCMAKE_BUILD_TYPE=Release >/dev/null &&
  cmake --build "$dir/build" -j "$JOBS" >/dev/null ||
  { echo "cross: the Cortex-M7 build failed (build/cross/cortex-m7/build)" >&2; exit 1; }

say "the same two programs on the host (build/examples)"
{ [ -f "$BUILD/CMakeCache.txt" ] || cmake -S "$ROOT" -B "$BUILD" >/dev/null; } &&
  cmake --build "$BUILD" -j "$JOBS" --target minimal fourbar_minimal >/dev/null ||
  { echo "cross: the host's build of the two programs failed (build/)" >&2; exit 1; }

fail=0
run() { # run NAME: the program on the board into build/cross/cortex-m7/NAME.txt
  timeout 600 "${QEMU[@]}" "$dir/build/$1.elf" >"$dir/$1.txt" || {
    echo "cross: $1 failed on the board (exit status $?)" >&2
    fail=1
  }
}
compare() { # compare NAME HOST_PROGRAM
  run "$1"
  "$BUILD/examples/$2" >"$dir/$1.host.txt"
  if cmp -s "$dir/$1.host.txt" "$dir/$1.txt"; then
    say "$1: the Cortex-M7's table equals the host's ($(wc -l <"$dir/$1.txt") lines)"
  else
    echo "cross: $1: the Cortex-M7's table differs from the host's:" >&2
    diff "$dir/$1.host.txt" "$dir/$1.txt" >&2 || true
    fail=1
  fi
}
compare oscillator minimal
compare fourbar fourbar_minimal
run probe

{
  echo "# stabdae on the Cortex-M7 (mps2-an500 under QEMU)"
  echo
  for name in oscillator fourbar; do
    echo "## $name: the board's table (equal to the host's: $(cmp -s "$dir/$name.host.txt" \
      "$dir/$name.txt" && echo yes || echo NO))"
    echo
    sed 's/^/    /' "$dir/$name.txt"
    echo
  done
  echo "## A step's block, stack and heap (probe)"
  echo
  cat "$dir/probe.txt"
  for name in oscillator fourbar probe; do
    echo
    echo "## Footprint of $name.elf (bytes; arm-none-eabi-size:" \
      "$(arm-none-eabi-size "$dir/build/$name.elf" | awk 'NR == 2 { print "text " $1 ", data " $2 ", bss " $3 }'))"
    echo
    awk -f "$ROOT/tools/cross/footprint.awk" "$dir/build/$name.elf.map"
  done
  echo
  echo "## The library's largest stack frames (-fstack-usage, bytes)"
  echo
  echo "| function | bytes | kind |"
  echo "|---|---:|---|"
  find "$dir/build/stabdae/src" -name '*.su' -exec cat {} + | sort -t$'\t' -k2,2nr |
    awk -F'\t' 'NR <= 8 { n = split($1, a, ":"); m = split(a[1], f, "/")
      printf "| %s: %s | %s | %s |\n", f[m], a[n], $2, $3 }'
} >"$dir/report.md"
say "report: build/cross/cortex-m7/report.md"
cat "$dir/report.md"
exit "$fail"
