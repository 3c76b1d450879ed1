# SPDX-License-Identifier: GPL-3.0-or-later
# What the two Linux toolchains share (included by aarch64-linux-gnu.cmake and
# arm-linux-gnueabihf.cmake, which set STABDAE_CROSS_TRIPLET and STABDAE_CROSS_QEMU): Debian's
# cross compiler of the triplet; the target's libraries and pkg-config files where Debian's
# multiarch packages put them (CMAKE_LIBRARY_ARCHITECTURE: the triplet's folder is searched,
# the host's is not); the host's headers, which serve both (GSL's below); the programs run by
# qemu-user, which finds the target's loader and libc in the same multiarch folders.
set(CMAKE_C_COMPILER ${STABDAE_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${STABDAE_CROSS_TRIPLET}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${STABDAE_CROSS_TRIPLET})
set(CMAKE_CROSSCOMPILING_EMULATOR ${STABDAE_CROSS_QEMU})

# programs (pkg-config, Python) of the host; headers and libraries from the cross root or the
# system's folders, the libraries by the multiarch triplet
set(CMAKE_FIND_ROOT_PATH /usr/${STABDAE_CROSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(ENV{PKG_CONFIG_LIBDIR}
    /usr/lib/${STABDAE_CROSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")

# GSL: Debian's libgsl-dev cannot be installed for two architectures at once (it holds
# gsl-config), so the target's runtime packages serve (libgsl27, libgslcblas0, by their
# sonames) with the host's headers, which are the same on every architecture.
foreach(lib gsl gslcblas)
  file(GLOB found /usr/lib/${STABDAE_CROSS_TRIPLET}/lib${lib}.so.[0-9]*)
  if(NOT found)
    message(FATAL_ERROR "no lib${lib}.so.* in /usr/lib/${STABDAE_CROSS_TRIPLET}: Debian's "
                        "libgsl27 and libgslcblas0 for the target (tools/cross/cross installs them)")
  endif()
  list(SORT found) # libgsl.so.27 before libgsl.so.27.0.0
  list(GET found 0 first)
  string(TOUPPER ${lib} name)
  string(REPLACE GSLCBLAS GSL_CBLAS name ${name})
  set(${name}_LIBRARY ${first} CACHE FILEPATH "the target's lib${lib} (toolchain file)")
endforeach()
