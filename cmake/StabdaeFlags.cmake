# SPDX-License-Identifier: GPL-3.0-or-later
# Compiler flags of stabdae's own targets. Nothing here is global (no add_compile_options,
# add_link_options or CMAKE_C_FLAGS): a parent project that pulls stabdae in with
# add_subdirectory or FetchContent keeps its own flags. The flags are GCC/Clang ones, each
# behind a compiler test; never -ffast-math (the NaN checks and the energy tests rely on IEEE
# arithmetic).
#
# stabdae_warnings: -Wall -Wextra -Wpedantic, and -Werror with STABDAE_WERROR.
# stabdae_instrument: AddressSanitizer and UndefinedBehaviorSanitizer with STABDAE_SANITIZE or
#   STABDAE_FUZZ, and libFuzzer's coverage feedback with STABDAE_FUZZ (the fuzz programs alone
#   link libFuzzer itself, tests/fuzz).
# stabdae_ieee: -ffp-contract=off: no multiply and add fused into one rounding. GCC does not fuse
#   in ISO C mode anyway; Clang does on targets with an FMA (aarch64, Cortex-M), and then the
#   same program prints other digits there than on x86-64 (docs/embedded.md).
# They are INTERFACE targets of the build tree only (not exported, not installed);
# stabdae_apply_flags links them to every target that stabdae's directories define.

set(stabdae_gnu_like "$<C_COMPILER_ID:GNU,Clang,AppleClang>")

add_library(stabdae_warnings INTERFACE)
target_compile_options(stabdae_warnings INTERFACE
  $<${stabdae_gnu_like}:-Wall -Wextra -Wpedantic>
  $<$<AND:$<BOOL:${STABDAE_WERROR}>,${stabdae_gnu_like}>:-Werror>)

add_library(stabdae_ieee INTERFACE)
target_compile_options(stabdae_ieee INTERFACE $<${stabdae_gnu_like}:-ffp-contract=off>)

add_library(stabdae_instrument INTERFACE)
if(STABDAE_SANITIZE OR STABDAE_FUZZ)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "^(GNU|Clang|AppleClang)$")
    message(FATAL_ERROR "STABDAE_SANITIZE needs GCC or Clang")
  endif()
  target_compile_options(stabdae_instrument INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(stabdae_instrument INTERFACE
    -fsanitize=address,undefined -fno-sanitize-recover=all)
endif()
if(STABDAE_FUZZ) # clang, checked by the top-level CMakeLists.txt
  target_compile_options(stabdae_instrument INTERFACE -fsanitize=fuzzer-no-link)
endif()

# stabdae_apply_flags(DIR): links stabdae_warnings, stabdae_ieee and stabdae_instrument
# privately to every target defined in the source directory DIR and the directories below it
# (INTERFACE libraries excepted, which compile nothing). $<BUILD_INTERFACE:...> keeps them out of the exported
# targets, where a static library lists even its private dependencies.
function(stabdae_apply_flags dir)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(NOT type STREQUAL "INTERFACE_LIBRARY" AND NOT type STREQUAL "UTILITY")
      target_link_libraries(${target} PRIVATE
        $<BUILD_INTERFACE:stabdae_warnings> $<BUILD_INTERFACE:stabdae_ieee>
        $<BUILD_INTERFACE:stabdae_instrument>)
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    stabdae_apply_flags(${subdir})
  endforeach()
endfunction()
