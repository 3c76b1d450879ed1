# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a program of tools/ida (ida_reference, ida_mbs) once and checks what the command-line
# rules promise.
#   cmake -DPROG=<program> -DARGS=<arguments separated by |> -DEXPECT=<exit status>
#         -DOUT=<the --out file of the run> [-DSTDOUT_REGEX=] [-DSTDERR_REGEX=] [-DFILE_REGEX=]
#         -P check_cli.cmake
# A nonzero exit must come with exactly one line on stderr; exit 2 (bad input) must leave no
# output file behind.
string(REPLACE "|" ";" args "${ARGS}")
get_filename_component(name "${PROG}" NAME)
file(REMOVE "${OUT}")
execute_process(COMMAND "${PROG}" ${args}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)

set(ran "${name} ${args}\n  exit ${rc}\n  stderr: ${err}")
if(NOT rc STREQUAL EXPECT)
  message(FATAL_ERROR "expected exit status ${EXPECT}: ${ran}")
endif()
if(NOT EXPECT EQUAL 0)
  string(REGEX MATCHALL "\n" newlines "${err}")
  list(LENGTH newlines lines)
  if(NOT lines EQUAL 1 OR NOT err MATCHES "^${name}: ")
    message(FATAL_ERROR "expected one line on stderr: ${ran}")
  endif()
endif()
if(EXPECT EQUAL 2 AND EXISTS "${OUT}")
  message(FATAL_ERROR "bad input left ${OUT} behind: ${ran}")
endif()
if(DEFINED STDOUT_REGEX AND NOT out MATCHES "${STDOUT_REGEX}")
  message(FATAL_ERROR "stdout does not match '${STDOUT_REGEX}': ${ran}\n  stdout: ${out}")
endif()
if(DEFINED STDERR_REGEX AND NOT err MATCHES "${STDERR_REGEX}")
  message(FATAL_ERROR "stderr does not match '${STDERR_REGEX}': ${ran}")
endif()
if(DEFINED FILE_REGEX)
  if(NOT EXISTS "${OUT}")
    message(FATAL_ERROR "no output file ${OUT}: ${ran}")
  endif()
  file(READ "${OUT}" content)
  if(NOT content MATCHES "${FILE_REGEX}")
    message(FATAL_ERROR "${OUT} does not match '${FILE_REGEX}': ${ran}\n${content}")
  endif()
endif()
