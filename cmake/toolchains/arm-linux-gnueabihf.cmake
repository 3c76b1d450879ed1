# SPDX-License-Identifier: GPL-3.0-or-later
# Cross-building for 32-bit ARM Linux (glibc, hard float) with Debian's
# gcc-arm-linux-gnueabihf, the libraries from Debian's multiarch packages (:armhf, in
# /usr/lib/arm-linux-gnueabihf), the tests run under qemu-user: tools/cross/cross armhf.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(STABDAE_CROSS_TRIPLET arm-linux-gnueabihf)
set(STABDAE_CROSS_QEMU qemu-arm)
include(${CMAKE_CURRENT_LIST_DIR}/linux-multiarch.cmake)
