# SPDX-License-Identifier: GPL-3.0-or-later
# stabdae_generate_mbs(NAME MODEL.py [TARGET TARGET] [OUTPUT_DIR DIR] [LIBRARY LIB]
#                      [DEPENDS FILE...])
#
# Generates NAME.h and NAME.c from MODEL.py (its mechanism() names the mechanism NAME) with
# the generator stabdae_gen (tools/mbsgen), again whenever MODEL.py or the generator changes,
# and adds them as a static library (PUBLIC: the directory of NAME.h, stabdae, libm) named
# TARGET, by default NAME. Use: target_link_libraries(app PRIVATE NAME), and #include "NAME.h".
# OUTPUT_DIR defaults to ${CMAKE_CURRENT_BINARY_DIR}/NAME; LIBRARY, the stabdae it links, to
# stabdae::stabdae (the shared library; stabdae::stabdae_static for the static one, and where
# there is no shared library, on a target without dynamic linking). DEPENDS
# names the files MODEL.py imports (a helper module beside it), to regenerate when they change.
#
# The generator needs Python 3 with sympy (tools/requirements.txt pins the version): the
# interpreter is STABDAE_GEN_PYTHON if set, else Python3_EXECUTABLE (find_package(Python3)).
# The same file serves the source tree and an install: who includes it sets STABDAE_GEN_PATH,
# the directory holding the package stabdae_gen (tools/ in the tree, share/stabdae/python once
# installed), kept in a global property for the calls from any directory.
if(NOT STABDAE_GEN_PATH OR NOT EXISTS "${STABDAE_GEN_PATH}/stabdae_gen/__init__.py")
  message(FATAL_ERROR "StabdaeGenerate.cmake: STABDAE_GEN_PATH '${STABDAE_GEN_PATH}' holds no "
                      "stabdae_gen")
endif()
set_property(GLOBAL PROPERTY STABDAE_GEN_PATH "${STABDAE_GEN_PATH}")

function(stabdae_generate_mbs name model)
  cmake_parse_arguments(PARSE_ARGV 2 arg "" "TARGET;OUTPUT_DIR;LIBRARY" "DEPENDS")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "stabdae_generate_mbs(${name} ...): unknown arguments "
                        "${arg_UNPARSED_ARGUMENTS} (NAME MODEL.py [TARGET T] [OUTPUT_DIR DIR] [LIBRARY LIB] [DEPENDS FILE...])")
  endif()
  set(target ${name})
  if(arg_TARGET)
    set(target ${arg_TARGET})
  endif()
  set(library stabdae::stabdae)
  if(NOT TARGET stabdae::stabdae)
    set(library stabdae::stabdae_static)
  endif()
  if(arg_LIBRARY)
    set(library ${arg_LIBRARY})
  endif()
  if(NOT name MATCHES "^[A-Za-z_][A-Za-z0-9_]*$")
    message(FATAL_ERROR "stabdae_generate_mbs: NAME '${name}' is not a C identifier")
  endif()
  get_filename_component(model "${model}" ABSOLUTE)
  if(NOT EXISTS "${model}")
    message(FATAL_ERROR "stabdae_generate_mbs(${name}): no file ${model}")
  endif()
  set(out "${CMAKE_CURRENT_BINARY_DIR}/${name}")
  if(arg_OUTPUT_DIR)
    get_filename_component(out "${arg_OUTPUT_DIR}" ABSOLUTE BASE_DIR
                           "${CMAKE_CURRENT_BINARY_DIR}")
  endif()
  _stabdae_gen_python(python)
  get_property(path GLOBAL PROPERTY STABDAE_GEN_PATH)
  file(GLOB generator_sources "${path}/stabdae_gen/*.py")
  # the generator first, then the user's own path (a model may import from it)
  set(pythonpath "${path}")
  if(DEFINED ENV{PYTHONPATH})
    string(APPEND pythonpath ":$ENV{PYTHONPATH}")
  endif()
  add_custom_command(
    OUTPUT "${out}/${name}.h" "${out}/${name}.c"
    COMMAND ${CMAKE_COMMAND} -E env "PYTHONPATH=${pythonpath}"
            "${python}" -m stabdae_gen "${model}" --out "${out}" --name ${name}
    DEPENDS "${model}" ${arg_DEPENDS} ${generator_sources}
    COMMENT "Generating the mechanism ${name} from ${model}"
    VERBATIM)
  add_library(${target} STATIC "${out}/${name}.c" "${out}/${name}.h")
  # position independent: the mechanism may go into a shared library or an FMU (stabdae_add_fmu)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC "${out}")
  target_link_libraries(${target} PUBLIC ${library} m)
endfunction()

# The interpreter that runs the generator, checked once for sympy.
function(_stabdae_gen_python var)
  if(NOT STABDAE_GEN_PYTHON)
    if(NOT Python3_EXECUTABLE)
      find_package(Python3 COMPONENTS Interpreter)
    endif()
    set(STABDAE_GEN_PYTHON "${Python3_EXECUTABLE}")
  endif()
  if(NOT STABDAE_GEN_PYTHON_CHECKED STREQUAL STABDAE_GEN_PYTHON)
    execute_process(COMMAND "${STABDAE_GEN_PYTHON}" -c "import sympy"
                    RESULT_VARIABLE missing OUTPUT_QUIET ERROR_QUIET)
    if(NOT STABDAE_GEN_PYTHON OR missing)
      message(FATAL_ERROR
        "stabdae_generate_mbs: no Python 3 with sympy ('${STABDAE_GEN_PYTHON}'): set "
        "STABDAE_GEN_PYTHON or Python3_EXECUTABLE to one (pip install -r "
        "tools/requirements.txt in a venv)")
    endif()
    set(STABDAE_GEN_PYTHON_CHECKED "${STABDAE_GEN_PYTHON}" CACHE INTERNAL "")
  endif()
  set(${var} "${STABDAE_GEN_PYTHON}" PARENT_SCOPE)
endfunction()
