# SPDX-License-Identifier: GPL-3.0-or-later
# What `cmake --install` puts under the prefix besides the libraries (src/CMakeLists.txt):
# the headers (the generated version.h among them), the CMake package (stabdaeConfig.cmake,
# its version file, the exported targets, StabdaeGenerate.cmake), the generator stabdae_gen
# (share/stabdae/python) and stabdae.pc. Off with STABDAE_INSTALL=OFF.
include(CMakePackageConfigHelpers)

set(STABDAE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/stabdae)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/stabdae
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h")
# generated from the project() line (src/CMakeLists.txt)
install(FILES ${PROJECT_BINARY_DIR}/include/stabdae/version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/stabdae)

install(EXPORT stabdaeTargets NAMESPACE stabdae:: DESTINATION ${STABDAE_CMAKE_DIR})
# the generator (Python, run at the user's build time by stabdae_generate_mbs) and its function
set(STABDAE_GEN_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/stabdae/python)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/stabdae_gen
  DESTINATION ${STABDAE_GEN_INSTALL_DIR}
  FILES_MATCHING PATTERN "*.py" PATTERN "tests" EXCLUDE PATTERN "__pycache__" EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/cmake/StabdaeGenerate.cmake ${PROJECT_SOURCE_DIR}/cmake/FindStabdaeSuiteSparse.cmake
  DESTINATION ${STABDAE_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/stabdaeConfig.cmake.in
  ${PROJECT_BINARY_DIR}/stabdaeConfig.cmake
  INSTALL_DESTINATION ${STABDAE_CMAKE_DIR}
  PATH_VARS STABDAE_GEN_INSTALL_DIR)
# The SONAME carries the major version, so the package promises the same.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/stabdaeConfigVersion.cmake
  COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/stabdaeConfig.cmake
  ${PROJECT_BINARY_DIR}/stabdaeConfigVersion.cmake
  DESTINATION ${STABDAE_CMAKE_DIR})

# stabdae.pc finds its prefix from its own place (${pcfiledir}), so that an install with
# `cmake --install --prefix` elsewhere than CMAKE_INSTALL_PREFIX still works; absolute
# install directories are written as they are.
function(stabdae_pc_dir var dir)
  if(IS_ABSOLUTE "${dir}")
    set(${var} "${dir}" PARENT_SCOPE)
  else()
    set(${var} "\${prefix}/${dir}" PARENT_SCOPE)
  endif()
endfunction()
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(STABDAE_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH up "/root/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/root")
  string(REGEX REPLACE "/$" "" up "${up}")
  set(STABDAE_PC_PREFIX "\${pcfiledir}/${up}")
endif()
stabdae_pc_dir(STABDAE_PC_LIBDIR "${CMAKE_INSTALL_LIBDIR}")
stabdae_pc_dir(STABDAE_PC_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/stabdae.pc.in ${PROJECT_BINARY_DIR}/stabdae.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/stabdae.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
