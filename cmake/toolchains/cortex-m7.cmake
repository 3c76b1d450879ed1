# SPDX-License-Identifier: GPL-3.0-or-later
# Bare metal on a Cortex-M7 with its double-precision FPU (fpv5-d16, hard float), Debian's
# gcc-arm-none-eabi with newlib, output by semihosting (rdimon); run on QEMU's mps2-an500.
# STABDAE_M7_SYSROOT (a cache variable) holds the target's GSL and SuiteSparse, include/ and
# lib/, built from Debian's sources by tools/cross/cortex-m7.sh.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY) # no program links without the board's files
# -fstack-usage: each object's frames beside it (.su), for docs/embedded.md
set(CMAKE_C_FLAGS_INIT "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb \
-ffunction-sections -fdata-sections -fstack-usage")
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=rdimon.specs -Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH ${STABDAE_M7_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
