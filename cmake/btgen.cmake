# btgen_add_mission(): compile a BehaviorTree.CPP v4 mission to C++ at build time.
#
#   btgen_add_mission(TARGET <name> MISSION <file.xml>
#                     [OUTPUT_DIR <dir>]          # default: <binary dir>/btgen/<name>
#                     [RELATIVE_TO <dir>]         # banner paths relative to it; default: the top source dir
#                     [SCENARIO_RUNNER <exe>]     # also build `exe SCENARIO_FILE` (the trace printer)
#                     [STRING_CAPACITY <n>]       # most bytes of a blackboard string (btgen compile --string-capacity)
#                     [QUEUE_CAPACITY <n>])       # most elements of a queue written by robot code
#
# creates a static library <name> holding the generated header and source
# (the header-only part is a class template over your leaves type; the
# source compiles the virtual-interface flavour once). Link it and include
# "<snake_case stem>.hpp".
#
# Dependencies are complete: the mission and every file it includes (found
# at configure time by `python -m btgen.compiler --deps`; editing a mission
# re-runs the configure step so a new include is seen), the generator's own
# Python sources, its templates and its schemas. The outputs are known at
# configure time (`--outputs`). Generation writes a file only when its bytes
# change (with Ninja, whose custom commands restat their outputs, an
# unchanged output does not rebuild what depends on it) and writes nothing
# when the mission has errors.
#
# Needs a Python with btgen's requirements (Jinja2, lxml, xmlschema): the one
# CMake found as Python3_EXECUTABLE (pass -DPython3_EXECUTABLE=.venv/bin/python).

include_guard(GLOBAL)

get_filename_component(_btgen_root "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
set_property(GLOBAL PROPERTY BTGEN_ROOT "${_btgen_root}")

if(NOT TARGET btgen_runtime)
  add_library(btgen_runtime INTERFACE)
  add_library(btgen::runtime ALIAS btgen_runtime)
  target_include_directories(btgen_runtime INTERFACE "${_btgen_root}/runtime/include")
  target_compile_features(btgen_runtime INTERFACE cxx_std_17)
endif()

# Runs `python -m btgen.compiler <args>` at configure time; the `;`-list it prints goes to <out_var>.
function(_btgen_query out_var)
  get_property(root GLOBAL PROPERTY BTGEN_ROOT)
  execute_process(
    COMMAND "${CMAKE_COMMAND}" -E env "PYTHONPATH=${root}/generator"
            "${Python3_EXECUTABLE}" -m btgen.compiler ${ARGN} --cmake
    OUTPUT_VARIABLE out
    ERROR_VARIABLE err
    RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "btgen: `python -m btgen.compiler ${ARGN}` failed (${rc}):\n${err}")
  endif()
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

# True in <out_var> when the C++ back end can compile <mission> (no diagnostics).
function(btgen_mission_compiles out_var mission)
  get_property(root GLOBAL PROPERTY BTGEN_ROOT)
  get_filename_component(mission "${mission}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  execute_process(
    COMMAND "${CMAKE_COMMAND}" -E env "PYTHONPATH=${root}/generator"
            "${Python3_EXECUTABLE}" -m btgen.compiler --check "${mission}"
    OUTPUT_QUIET ERROR_QUIET
    RESULT_VARIABLE rc)
  if(rc EQUAL 0)
    set(${out_var} TRUE PARENT_SCOPE)
  else()
    set(${out_var} FALSE PARENT_SCOPE)
  endif()
endfunction()

function(btgen_add_mission)
  cmake_parse_arguments(ARG "" "TARGET;MISSION;OUTPUT_DIR;RELATIVE_TO;SCENARIO_RUNNER;STRING_CAPACITY;QUEUE_CAPACITY"
                        "" ${ARGN})
  if(NOT ARG_TARGET OR NOT ARG_MISSION)
    message(FATAL_ERROR "btgen_add_mission: TARGET and MISSION are required")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "btgen_add_mission: unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT Python3_EXECUTABLE)
    find_package(Python3 REQUIRED COMPONENTS Interpreter)
  endif()
  get_property(root GLOBAL PROPERTY BTGEN_ROOT)
  get_filename_component(mission "${ARG_MISSION}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  if(NOT EXISTS "${mission}")
    message(FATAL_ERROR "btgen_add_mission: mission ${mission} does not exist")
  endif()
  if(ARG_OUTPUT_DIR)
    get_filename_component(out_dir "${ARG_OUTPUT_DIR}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
  else()
    set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/btgen/${ARG_TARGET}")
  endif()
  if(ARG_RELATIVE_TO)
    get_filename_component(relative_to "${ARG_RELATIVE_TO}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  else()
    set(relative_to "${CMAKE_SOURCE_DIR}")
  endif()

  _btgen_query(deps --deps "${mission}")
  _btgen_query(names --outputs "${mission}")
  _btgen_query(generator_inputs --inputs)
  # Editing the mission or an include re-runs configure, which refreshes the include list.
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${deps})

  set(outputs "")
  foreach(name IN LISTS names)
    list(APPEND outputs "${out_dir}/${name}")
  endforeach()
  list(GET names 0 header_name)

  set(capacities "")
  if(ARG_STRING_CAPACITY)
    list(APPEND capacities --string-capacity ${ARG_STRING_CAPACITY})
  endif()
  if(ARG_QUEUE_CAPACITY)
    list(APPEND capacities --queue-capacity ${ARG_QUEUE_CAPACITY})
  endif()

  add_custom_command(
    OUTPUT ${outputs}
    COMMAND "${CMAKE_COMMAND}" -E env "PYTHONPATH=${root}/generator"
            "${Python3_EXECUTABLE}" -m btgen compile "${mission}" -o "${out_dir}" --relative-to "${relative_to}"
            ${capacities}
    DEPENDS ${deps} ${generator_inputs}
    WORKING_DIRECTORY "${relative_to}"
    COMMENT "btgen: generating C++ for ${ARG_MISSION}"
    VERBATIM)

  add_library(${ARG_TARGET} STATIC ${outputs})
  target_include_directories(${ARG_TARGET} PUBLIC "${out_dir}")
  target_link_libraries(${ARG_TARGET} PUBLIC btgen::runtime)
  target_compile_features(${ARG_TARGET} PUBLIC cxx_std_17)
  if(DEFINED BTGEN_WARNINGS)
    target_compile_options(${ARG_TARGET} PRIVATE ${BTGEN_WARNINGS})
  endif()
  set_target_properties(${ARG_TARGET} PROPERTIES
    BTGEN_HEADER "${header_name}"
    BTGEN_MISSION "${mission}")

  if(ARG_SCENARIO_RUNNER)
    _btgen_query(template --template "${mission}")
    add_executable(${ARG_SCENARIO_RUNNER} "${root}/runtime/src/main_driver.cpp")
    target_link_libraries(${ARG_SCENARIO_RUNNER} PRIVATE ${ARG_TARGET})
    target_compile_definitions(${ARG_SCENARIO_RUNNER} PRIVATE
      "BTGEN_MISSION_HEADER=\"${header_name}\""
      "BTGEN_MISSION_TEMPLATE=${template}")
    if(DEFINED BTGEN_WARNINGS)
      target_compile_options(${ARG_SCENARIO_RUNNER} PRIVATE ${BTGEN_WARNINGS})
    endif()
  endif()
endfunction()
