# SPDX-License-Identifier: GPL-3.0-or-later
# The parts of SuiteSparse stabdae's sparse mechanisms use (src/core/sparse_ldl.c): LDL, AMD
# and SuiteSparse_config under them, as imported targets SuiteSparse::LDL, SuiteSparse::AMD
# and SuiteSparse::SuiteSparseConfig (the names SuiteSparse 7's own CMake packages give them;
# targets already defined are kept). Debian's SuiteSparse 5 ships no CMake package: its headers
# are in include/suitesparse. Named for stabdae, so that a consumer's own FindSuiteSparse.cmake
# is neither shadowed nor shadows it. StabdaeSuiteSparse_STATIC_LIBRARIES lists the three
# static archives when all are found (the FMUs link them in), and is empty otherwise.
include(FindPackageHandleStandardArgs)

find_path(SuiteSparse_INCLUDE_DIR NAMES ldl.h amd.h PATH_SUFFIXES suitesparse)
set(StabdaeSuiteSparse_STATIC_LIBRARIES)
foreach(part LDL AMD SuiteSparseConfig)
  string(TOLOWER ${part} lib)
  find_library(SuiteSparse_${part}_LIBRARY NAMES ${lib})
  find_library(SuiteSparse_${part}_STATIC NAMES lib${lib}.a)
  if(SuiteSparse_${part}_STATIC)
    list(APPEND StabdaeSuiteSparse_STATIC_LIBRARIES ${SuiteSparse_${part}_STATIC})
  endif()
  mark_as_advanced(SuiteSparse_${part}_LIBRARY SuiteSparse_${part}_STATIC)
endforeach()
mark_as_advanced(SuiteSparse_INCLUDE_DIR)
list(LENGTH StabdaeSuiteSparse_STATIC_LIBRARIES found)
if(NOT found EQUAL 3)
  set(StabdaeSuiteSparse_STATIC_LIBRARIES)
endif()

find_package_handle_standard_args(StabdaeSuiteSparse
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR SuiteSparse_LDL_LIBRARY SuiteSparse_AMD_LIBRARY
                SuiteSparse_SuiteSparseConfig_LIBRARY)

if(StabdaeSuiteSparse_FOUND)
  foreach(part SuiteSparseConfig AMD LDL)
    if(NOT TARGET SuiteSparse::${part})
      add_library(SuiteSparse::${part} UNKNOWN IMPORTED)
      set_target_properties(SuiteSparse::${part} PROPERTIES
        IMPORTED_LOCATION ${SuiteSparse_${part}_LIBRARY}
        INTERFACE_INCLUDE_DIRECTORIES ${SuiteSparse_INCLUDE_DIR})
    endif()
  endforeach()
  set_property(TARGET SuiteSparse::AMD APPEND PROPERTY
    INTERFACE_LINK_LIBRARIES SuiteSparse::SuiteSparseConfig)
endif()
