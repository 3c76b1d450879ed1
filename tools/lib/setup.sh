# SPDX-License-Identifier: GPL-3.0-or-later
# Shared set-up of tools/check and tools/demo (sourced): the system packages, the Python venv
# under build/, and the configured and built tree. Works on a fresh Debian or Ubuntu machine.

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD="$ROOT/build"
JOBS=$(nproc 2>/dev/null || echo 2)

say() { printf '== %s\n' "$*"; }

# Debian package names of what is missing.
missing_packages() {
  local pkgs=()
  command -v cmake >/dev/null || pkgs+=(cmake)
  command -v cc >/dev/null || pkgs+=(gcc)
  command -v make >/dev/null || pkgs+=(make)
  command -v pkg-config >/dev/null || pkgs+=(pkg-config)
  pkg-config --exists gsl 2>/dev/null || pkgs+=(libgsl-dev)
  pkg-config --exists check 2>/dev/null || pkgs+=(check)
  [ -e /usr/include/suitesparse/ldl.h ] || pkgs+=(libsuitesparse-dev)
  ls /usr/lib/*/cmake/sundials/SUNDIALSConfig.cmake >/dev/null 2>&1 || pkgs+=(libsundials-dev)
  python3 -c 'import ensurepip, venv' 2>/dev/null || pkgs+=(python3-venv)
  for tool in "$@"; do
    case $tool in
      fuzzer) # clang, then its libFuzzer runtime (a package of its own on Debian)
        if ! command -v clang >/dev/null; then pkgs+=(clang)
        elif ! clang_links_fuzzer; then pkgs+=("$(fuzzer_runtime_package)")
        fi ;;
      mpi) # Open MPI: the ensemble runner's headers and library, and mpirun for its tests
        pkg-config --exists ompi-c 2>/dev/null || pkgs+=(libopenmpi-dev)
        command -v mpirun >/dev/null || pkgs+=(openmpi-bin) ;;
      *) command -v "$tool" >/dev/null || pkgs+=("$tool") ;;
    esac
  done
  echo "${pkgs[@]}"
}

# Whether clang links a fuzz target with -fsanitize=fuzzer,address,undefined.
clang_links_fuzzer() {
  local dir rc
  dir=$(mktemp -d)
  printf '%s\n' '#include <stddef.h>' '#include <stdint.h>' \
    'int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }' \
    >"$dir/t.c"
  clang -fsanitize=fuzzer,address,undefined "$dir/t.c" -o "$dir/t" >/dev/null 2>&1
  rc=$?
  rm -rf "$dir"
  return $rc
}

# libclang-rt-N-dev (Debian 12, Ubuntu 23.04 on) or libclang-common-N-dev (older), N = clang's
# major version.
fuzzer_runtime_package() {
  local v
  v=$(clang -dumpversion | cut -d. -f1)
  if apt-cache show "libclang-rt-$v-dev" >/dev/null 2>&1; then
    echo "libclang-rt-$v-dev"
  else
    echo "libclang-common-$v-dev"
  fi
}

# Installs the missing packages with apt-get when root; otherwise prints the command and stops.
# Arguments: extra commands whose Debian package has the same name (valgrind), `fuzzer`
# for clang with its libFuzzer runtime, and `mpi` for Open MPI (examples/ensemble). Two rounds, because the runtime's package name is
# known only once clang is there.
ensure_packages() {
  local pkgs round
  for round in 1 2; do
    pkgs=$(missing_packages "$@")
    [ -z "$pkgs" ] && return 0
    if [ "$(id -u)" -ne 0 ] || ! command -v apt-get >/dev/null; then
      echo "stabdae needs these Debian packages: $pkgs" >&2
      echo "install them with: sudo apt-get install -y $pkgs" >&2
      exit 2
    fi
    export DEBIAN_FRONTEND=noninteractive
    [ "$round" -eq 1 ] && apt-get update -qq
    pkgs=$(missing_packages "$@") # again, now that apt knows the package names
    say "installing system packages: $pkgs"
    # shellcheck disable=SC2086
    apt-get install -y -qq --no-install-recommends $pkgs >/dev/null
  done
  pkgs=$(missing_packages "$@")
  if [ -n "$pkgs" ]; then
    echo "still missing after apt-get install: $pkgs" >&2
    exit 2
  fi
}

# build/venv with tools/requirements.txt, reinstalled only when the requirements change.
ensure_venv() {
  local req="$ROOT/tools/requirements.txt" stamp="$BUILD/venv/.requirements"
  mkdir -p "$BUILD"
  if [ ! -x "$BUILD/venv/bin/python" ]; then
    say "creating the Python venv in build/venv"
    python3 -m venv "$BUILD/venv"
  fi
  if ! cmp -s "$req" "$stamp"; then
    say "installing the pinned Python packages"
    "$BUILD/venv/bin/python" -m pip install -q --disable-pip-version-check -r "$req"
    cp "$req" "$stamp"
  fi
  PYTHON="$BUILD/venv/bin/python"
}

# configure_and_build DIR [cmake options...]
configure_and_build() {
  local dir=$1
  shift
  say "configuring and building ${dir#"$ROOT"/}"
  # the venv's Python for every tree; one without the Python tests does not warn about it
  cmake -S "$ROOT" -B "$dir" --no-warn-unused-cli -DSTABDAE_WERROR=ON \
    -DPython3_EXECUTABLE="${PYTHON:-python3}" \
    "$@" >/dev/null
  cmake --build "$dir" -j "$JOBS" >/dev/null
}
