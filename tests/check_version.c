/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The version has one source, the project() line of CMakeLists.txt: sdae_version() at run time,
 * the SDAE_VERSION_* macros of the generated <stabdae/version.h>, and the version CMake passes
 * to this suite as EXPECTED_VERSION (tests/CMakeLists.txt) all say the same. */
#include <stdio.h>

#include "testmodels.h"

#ifndef EXPECTED_VERSION
#error "tests/CMakeLists.txt passes EXPECTED_VERSION, the project() line's version"
#endif

START_TEST(matches_cmake_project_version) {
  ck_assert_ptr_nonnull(sdae_version());
  ck_assert_str_eq(sdae_version(), EXPECTED_VERSION);
  ck_assert_str_eq(SDAE_VERSION_STRING, EXPECTED_VERSION);
}
END_TEST

START_TEST(matches_the_macros) {
  char joined[64];
  int n = snprintf(joined, sizeof joined, "%d.%d.%d", SDAE_VERSION_MAJOR, SDAE_VERSION_MINOR,
                   SDAE_VERSION_PATCH);
  ck_assert_int_gt(n, 0);
  ck_assert_int_lt(n, (int)sizeof joined);
  ck_assert_str_eq(sdae_version(), joined);
  /* the macros are numbers a preprocessor can compare */
#if SDAE_VERSION_MAJOR < 0 || SDAE_VERSION_MINOR < 0 || SDAE_VERSION_PATCH < 0
  ck_abort_msg("negative version component");
#endif
}
END_TEST

/* a static string: never freed, the same every call */
START_TEST(is_the_same_string_every_call) {
  const char *first = sdae_version();
  ck_assert_ptr_eq(sdae_version(), first);
}
END_TEST

int main(void) {
  Suite *s = suite_create("version");
  ADD_CASE(s, matches_cmake_project_version);
  ADD_CASE(s, matches_the_macros);
  ADD_CASE(s, is_the_same_string_every_call);
  return run_suite(s);
}
