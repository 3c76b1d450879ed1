# SPDX-License-Identifier: GPL-3.0-or-later
# stabdae_add_fmu: a mechanism of <stabdae/mbs.h>, described by its table (<stabdae/fmu.h>), as
# an FMI 3.0 and an FMI 2.0 co-simulation FMU (docs/fmi.md). In stabdae's tree and after
# find_package(stabdae) alike:
#
#   stabdae_add_fmu(NAME SOURCES file.c ... [LIBRARIES lib ...] [INCLUDE_DIRECTORIES dir ...]
#                   [OUTPUT_DIRECTORY dir])
#
# builds OUTPUT_DIRECTORY/fmi3/NAME.fmu and OUTPUT_DIRECTORY/fmi2/NAME.fmu (default: the current
# binary directory) with the target NAME_fmu, part of `all`. Each FMU holds modelDescription.xml
# (written at build time by NAME_describe from the same table as the binary), the binary
# binaries/<platform>/NAME.so with stabdae, SuiteSparse's LDL and AMD, GSL and GSL's CBLAS
# linked in, and documentation/ (a page on the variables, the licences). The binary exports the FMI functions only and needs
# libc and libm alone: its GSL calls the CBLAS inside it, whatever cblas_* the importer's process
# loaded before (a shared CBLAS beside it would be bound to the first one loaded). Linux on
# x86_64 (FMI platforms x86_64-linux and linux64).
#
# What it reads: the targets stabdae::stabdae_fmi3, stabdae::stabdae_fmi2,
# stabdae::stabdae_fmu_describe, and STABDAE_FMU_DATA (the export maps and the licences).

include_guard(GLOBAL)

if(NOT DEFINED STABDAE_FMU_DATA)
  set(STABDAE_FMU_DATA ${CMAKE_CURRENT_LIST_DIR}/fmi)
endif()

# GSL and its CBLAS as static archives: libgsl.a is position independent on Debian; the objects
# of libgslcblas.a are position-independent executable code, which links into a shared object
# when its symbols bind inside it (the version script makes them local) but for the error
# handler xerbla.o, which stabdae_fmi3 and stabdae_fmi2 replace (fmi/fmu_cblas_xerbla.c)
find_library(STABDAE_GSL_STATIC NAMES libgsl.a)
find_library(STABDAE_GSLCBLAS_STATIC NAMES libgslcblas.a)

function(stabdae_add_fmu name)
  cmake_parse_arguments(PARSE_ARGV 1 fmu "" "OUTPUT_DIRECTORY" "SOURCES;LIBRARIES;INCLUDE_DIRECTORIES")
  if(NOT fmu_SOURCES)
    message(FATAL_ERROR "stabdae_add_fmu(${name}): SOURCES is required")
  endif()
  if(CMAKE_VERSION VERSION_LESS 3.24)
    message(FATAL_ERROR "stabdae_add_fmu needs CMake 3.24 (LINK_LIBRARY:WHOLE_ARCHIVE)")
  endif()
  if(NOT CMAKE_SYSTEM_NAME STREQUAL "Linux" OR NOT CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
    message(FATAL_ERROR "stabdae_add_fmu: Linux on x86_64 only (FMI platform x86_64-linux)")
  endif()
  if(NOT STABDAE_GSL_STATIC OR NOT STABDAE_GSLCBLAS_STATIC)
    message(FATAL_ERROR "stabdae_add_fmu: libgsl.a and libgslcblas.a are needed "
                        "(Debian: libgsl-dev)")
  endif()
  if(NOT StabdaeSuiteSparse_STATIC_LIBRARIES)
    message(FATAL_ERROR "stabdae_add_fmu: libldl.a, libamd.a and libsuitesparseconfig.a are "
                        "needed (Debian: libsuitesparse-dev)")
  endif()
  if(NOT fmu_OUTPUT_DIRECTORY)
    set(fmu_OUTPUT_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  endif()

  # the model's own code, compiled once for the binaries and the describer
  add_library(${name}_model OBJECT ${fmu_SOURCES})
  set_target_properties(${name}_model PROPERTIES POSITION_INDEPENDENT_CODE ON
                                                 C_VISIBILITY_PRESET hidden)
  target_include_directories(${name}_model PRIVATE ${fmu_INCLUDE_DIRECTORIES})
  target_link_libraries(${name}_model PUBLIC stabdae::stabdae_fmi ${fmu_LIBRARIES})

  add_executable(${name}_describe $<TARGET_OBJECTS:${name}_model>)
  target_link_libraries(${name}_describe PRIVATE stabdae::stabdae_fmu_describe ${fmu_LIBRARIES})

  set(stage_root ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmu)
  set(fmus)
  foreach(version 3 2)
    if(version EQUAL 3)
      set(platform x86_64-linux)
      set(page index.html)
    else()
      set(platform linux64)
      set(page _main.html)
    endif()
    set(lib ${name}_fmi${version})
    add_library(${lib} SHARED $<TARGET_OBJECTS:${name}_model>)
    # the FMI functions whole (nothing in the FMU calls them), then stabdae, GSL and its CBLAS
    # linked in; --as-needed drops the shared libgsl and libgslcblas that GSL::gsl names, every
    # symbol found in the archives
    target_link_libraries(${lib} PRIVATE
      "$<LINK_LIBRARY:WHOLE_ARCHIVE,stabdae::stabdae_fmi${version}>" stabdae::stabdae_fmi
      ${fmu_LIBRARIES} stabdae::stabdae_static ${StabdaeSuiteSparse_STATIC_LIBRARIES}
      ${STABDAE_GSL_STATIC} ${STABDAE_GSLCBLAS_STATIC}
      m)
    target_link_options(${lib} PRIVATE -Wl,--as-needed
                        -Wl,--version-script=${STABDAE_FMU_DATA}/fmi${version}.map)
    # every symbol resolved at link time (a table the sources forgot fails here, not at
    # dlopen), but under stabdae's sanitizers: clang leaves a shared object's __asan_* to the
    # program's runtime
    if(NOT STABDAE_SANITIZE AND NOT STABDAE_FUZZ)
      target_link_options(${lib} PRIVATE -Wl,--no-undefined)
    endif()
    set_target_properties(${lib} PROPERTIES
      PREFIX "" OUTPUT_NAME ${name}
      LIBRARY_OUTPUT_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}/${name}_fmi${version}_binary
      SKIP_BUILD_RPATH ON
      LINK_DEPENDS ${STABDAE_FMU_DATA}/fmi${version}.map)

    set(stage ${stage_root}/fmi${version})
    set(bin ${stage}/binaries/${platform})
    set(fmu ${fmu_OUTPUT_DIRECTORY}/fmi${version}/${name}.fmu)
    add_custom_command(OUTPUT ${fmu}
      COMMAND ${CMAKE_COMMAND} -E rm -rf ${stage}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${bin} ${stage}/documentation/licenses
              ${fmu_OUTPUT_DIRECTORY}/fmi${version}
      COMMAND ${name}_describe ${version} ${stage}/modelDescription.xml
              ${stage}/documentation/${page} ${name}
      COMMAND ${CMAKE_COMMAND} -E copy $<TARGET_FILE:${lib}> ${bin}/${name}.so
      COMMAND ${CMAKE_COMMAND} -E copy_directory ${STABDAE_FMU_DATA}/licenses
              ${stage}/documentation/licenses
      COMMAND ${CMAKE_COMMAND} -E rm -f ${fmu}
      COMMAND ${CMAKE_COMMAND} -E chdir ${stage} ${CMAKE_COMMAND} -E tar cf ${fmu} --format=zip
              modelDescription.xml binaries documentation
      DEPENDS ${lib} ${name}_describe ${STABDAE_FMU_DATA}/licenses/license.txt
      COMMENT "FMU ${fmu}"
      VERBATIM)
    list(APPEND fmus ${fmu})
  endforeach()
  add_custom_target(${name}_fmu ALL DEPENDS ${fmus})
endfunction()
