# SPDX-License-Identifier: GPL-3.0-or-later
# Cross-building for 64-bit ARM Linux (glibc) with Debian's gcc-aarch64-linux-gnu, the
# libraries from Debian's multiarch packages (libgsl27:arm64, libsuitesparse-dev:arm64,
# check:arm64 in /usr/lib/aarch64-linux-gnu), the tests run under qemu-user. tools/cross/cross
# installs all of it: tools/cross/cross aarch64.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(STABDAE_CROSS_TRIPLET aarch64-linux-gnu)
set(STABDAE_CROSS_QEMU qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/linux-multiarch.cmake)
