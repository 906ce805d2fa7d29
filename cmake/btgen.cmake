# btgen_add_mission(): compile a BehaviorTree.CPP v4 mission to C++ at build time.
#
#   btgen_add_mission(<target> MISSION <file.xml>
#                     [NAMESPACE <ns>]            # C++ namespace (btgen compile --namespace); default from the file name
#                     [MAIN_TREE <id>]            # the tree to run (btgen compile --main-tree)
#                     [MODELS <file.xml>...]      # files of <TreeNodesModel> declarations (btgen compile --models)
#                     [TREES <file.xml|dir>...]   # BehaviorTrees the mission's SubTrees may use (btgen compile --trees)
#                     [ENTRIES <[TREE:]NAME=TYPE>...]  # entries the application sets before the first tick
#                                                 # (btgen compile --entry; the mission gets provide_<entry>())
#                     [ENUMS <Type=A,B,C>...]     # scripting enums (btgen compile --enum)
#                     [ENUM_FILES <file>...]      # files of scripting enums (btgen compile --enums)
#                     [TYPES <NAME=CPP_TYPE@HEADER>...]  # user port types (btgen compile --type); the
#                                                 # target needs HEADER's folder on its include path;
#                                                 # a type may own memory (ROS messages, std::vector:
#                                                 # its own copies allocate; docs/types.md)
#                     [STRING_CAPACITY <n>]       # most bytes of a blackboard string (btgen compile --string-capacity)
#                     [QUEUE_CAPACITY <n>]        # most elements of a queue written by robot code
#                     [BTCPP_VERSION <4.6.2|4.10.0>]  # the BehaviorTree.CPP release to follow (btgen --btcpp);
#                                                 # default 4.6.2; one program follows one release
#                     [OUTPUT_DIR <dir>]          # default: <binary dir>/btgen/<target>
#                     [RELATIVE_TO <dir>]         # banner paths relative to it; default: the top source dir
#                     [SCENARIO_RUNNER <exe>])    # also build `exe SCENARIO_FILE` (the trace printer)
#
# `btgen_add_mission(TARGET <target> MISSION ...)` is the same.
#
# creates a static library <target> holding the generated header and source
# (the header-only part is a class template over your leaves type; the
# source compiles the virtual-interface flavour once). Link it and include
# "<snake_case stem>.hpp". The target's BTGEN_HEADER property names the
# header.
#
# Dependencies are complete: the mission, every file it includes and the
# MODELS files (found at configure time by `btgen build-info --deps`; editing
# one re-runs the configure step so a new include is seen), btgen itself
# (its command, Python sources, templates and schemas). The outputs are known
# at configure time (`--outputs`). Generation writes a file only when its
# bytes change (with Ninja, whose custom commands restat their outputs, an
# unchanged output does not rebuild what depends on it) and writes nothing
# when the mission has errors: the build fails with btgen's
# `path:line:col: error:` lines.
#
# How btgen runs: BTGEN_EXECUTABLE, the installed `btgen` command (the CMake
# package, find_package(btgen), sets it to the command installed with it);
# without it, `python -m btgen` from this checkout's generator/ with
# Python3_EXECUTABLE, a Python that has btgen's requirements (Jinja2, lxml,
# xmlschema): pass -DPython3_EXECUTABLE=.venv/bin/python.
#
# Targets: btgen::runtime (header only, C++17) and btgen::scenario (the
# scenario harness, btgen/harness/) always; btgen::kb (the
# environment knowledge base reader, needs Eigen) when Eigen3::Eigen exists
# (see _btgen_define_kb); btgen::btlog and btgen::groot2 (Groot2 monitors, the
# latter needs cppzmq) when their dependencies are targets (see
# _btgen_define_monitors).

include_guard(GLOBAL)

get_filename_component(_btgen_root "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
set_property(GLOBAL PROPERTY BTGEN_ROOT "${_btgen_root}")

# ==== btgen::runtime: header-only runtime of generated missions (the one definition)
if(NOT TARGET btgen_runtime)
  add_library(btgen_runtime INTERFACE)
  add_library(btgen::runtime ALIAS btgen_runtime)
  target_include_directories(btgen_runtime INTERFACE "${_btgen_root}/runtime/include")
  target_compile_features(btgen_runtime INTERFACE cxx_std_17)
endif()

# ==== btgen::scenario: the scenario harness (btgen/harness/*.hpp): reads scenario files
# and runs a mission on scripted leaves, printing the status trace. For simulators, tests and
# the SCENARIO_RUNNER of btgen_add_mission; it allocates (std::string, std::vector) and is
# not part of what a mission on the robot needs.
if(NOT TARGET btgen_scenario)
  add_library(btgen_scenario INTERFACE)
  add_library(btgen::scenario ALIAS btgen_scenario)
  target_link_libraries(btgen_scenario INTERFACE btgen_runtime)
endif()

# ==== btgen::kb: EnvironmentKnowledgeBase, defined when Eigen3::Eigen is a target
function(_btgen_define_kb)
  if(TARGET btgen_kb OR NOT TARGET Eigen3::Eigen)
    return()
  endif()
  get_property(root GLOBAL PROPERTY BTGEN_ROOT)
  add_library(btgen_kb STATIC "${root}/runtime/src/environment_knowledge_base.cpp")
  add_library(btgen::kb ALIAS btgen_kb)
  target_include_directories(btgen_kb PUBLIC "${root}/runtime/include")
  target_link_libraries(btgen_kb PUBLIC Eigen3::Eigen)
  target_compile_features(btgen_kb PUBLIC cxx_std_17)
endfunction()

# ==== btgen::btlog, btgen::groot2: run-time monitors (opt-in)
# btgen::btlog writes Groot2 .btlog files (include/btgen/btlog.hpp, a writer
# thread: needs Threads). btgen::groot2 is the Groot2 live publisher
# (include/btgen/groot2.hpp) over ZeroMQ: defined only when the `cppzmq` target
# exists (find_package(cppzmq), Debian's cppzmq-dev). A mission linking neither
# needs no ZeroMQ and no threads. Groot2's REPLACE hooks (live fault injection)
# work in every build; its breakpoints, which pause the tick thread, only with
# BTGEN_GROOT2_BREAKPOINTS=ON (a debug build's option: without it a breakpoint
# request gets an error reply).
option(BTGEN_GROOT2_BREAKPOINTS "Groot2 breakpoints may pause the tick thread (debug builds)" OFF)
function(_btgen_define_monitors)
  if(NOT TARGET btgen_btlog AND TARGET Threads::Threads)
    add_library(btgen_btlog INTERFACE)
    add_library(btgen::btlog ALIAS btgen_btlog)
    target_link_libraries(btgen_btlog INTERFACE btgen::runtime Threads::Threads)
  endif()
  if(NOT TARGET btgen_groot2 AND TARGET btgen_btlog AND TARGET cppzmq)
    add_library(btgen_groot2 INTERFACE)
    add_library(btgen::groot2 ALIAS btgen_groot2)
    target_link_libraries(btgen_groot2 INTERFACE btgen::btlog cppzmq)
    if(BTGEN_GROOT2_BREAKPOINTS)
      target_compile_definitions(btgen_groot2 INTERFACE BTGEN_GROOT2_BREAKPOINTS)
    endif()
  endif()
endfunction()

# The command that runs btgen, in <out_var> (a list).
function(_btgen_command out_var)
  if(BTGEN_EXECUTABLE)
    set(${out_var} "${BTGEN_EXECUTABLE}" PARENT_SCOPE)
    return()
  endif()
  if(NOT Python3_EXECUTABLE)
    find_package(Python3 REQUIRED COMPONENTS Interpreter)
  endif()
  get_property(root GLOBAL PROPERTY BTGEN_ROOT)
  set(${out_var} "${CMAKE_COMMAND}" -E env "PYTHONPATH=${root}/generator" "${Python3_EXECUTABLE}" -m btgen
      PARENT_SCOPE)
endfunction()

# Runs `btgen build-info <args> --cmake` at configure time; the `;`-list it prints goes to <out_var>.
function(_btgen_query out_var)
  _btgen_command(cmd)
  execute_process(
    COMMAND ${cmd} build-info ${ARGN} --cmake
    OUTPUT_VARIABLE out
    ERROR_VARIABLE err
    RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " shown "${ARGN}")
    message(FATAL_ERROR "btgen: `btgen build-info ${shown}` failed (${rc}):\n${err}")
  endif()
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

# The keywords of btgen_add_mission that are mission options of every btgen command
# (generator/btgen/pipeline.py), in a global property (a variable set here would not reach
# a function called from another directory once the include guard skips this file).
set_property(GLOBAL PROPERTY BTGEN_ONE_VALUE_OPTIONS "NAMESPACE;MAIN_TREE;STRING_CAPACITY;QUEUE_CAPACITY;BTCPP_VERSION")
set_property(GLOBAL PROPERTY BTGEN_MULTI_VALUE_OPTIONS "MODELS;TREES;ENTRIES;ENUMS;ENUM_FILES;TYPES")

# `<flag> <value>` appended to the list <options_var> (in the caller's scope) for each value
# of the list <values>.
function(_btgen_flag_each options_var flag values)
  set(options "${${options_var}}")
  foreach(value IN LISTS values)
    list(APPEND options ${flag} "${value}")
  endforeach()
  set(${options_var} "${options}" PARENT_SCOPE)
endfunction()

# The files of the list <files>, absolute (a relative one is taken from
# CMAKE_CURRENT_SOURCE_DIR), in <out_var>; a missing one stops the configure step with
# `<caller>: <what> <file> does not exist`.
function(_btgen_existing_files out_var caller what files)
  set(found "")
  foreach(file IN LISTS files)
    get_filename_component(file "${file}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
    if(NOT EXISTS "${file}")
      message(FATAL_ERROR "${caller}: ${what} ${file} does not exist")
    endif()
    list(APPEND found "${file}")
  endforeach()
  set(${out_var} "${found}" PARENT_SCOPE)
endfunction()

# From the caller's parsed ARG_<keyword> variables: `read_options` (what changes what is
# read: --models, --main-tree), `write_options` (the rest: --namespace, capacities, enums,
# types), `ns_option` and `option_files` (files named by options, for dependencies), set in
# the caller's scope. Relative files are taken from CMAKE_CURRENT_SOURCE_DIR.
function(_btgen_collect_options caller)
  set(read_options "")
  _btgen_existing_files(models_files ${caller} "models file" "${ARG_MODELS}")
  _btgen_flag_each(read_options --models "${models_files}")
  # Tree libraries: a file, or a folder whose *.xml files are read (the folder itself is a
  # configure dependency, so a file added to it is seen).
  _btgen_existing_files(trees_files ${caller} "trees file or folder" "${ARG_TREES}")
  _btgen_flag_each(read_options --trees "${trees_files}")
  foreach(trees IN LISTS trees_files)
    if(IS_DIRECTORY "${trees}")
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${trees}")
    endif()
  endforeach()
  if(DEFINED ARG_MAIN_TREE)
    list(APPEND read_options --main-tree "${ARG_MAIN_TREE}")
  endif()
  if(DEFINED ARG_BTCPP_VERSION)
    list(APPEND read_options --btcpp "${ARG_BTCPP_VERSION}")
  endif()
  _btgen_flag_each(read_options --entry "${ARG_ENTRIES}")
  set(ns_option "")
  if(DEFINED ARG_NAMESPACE)
    set(ns_option --namespace "${ARG_NAMESPACE}")
  endif()
  set(write_options ${ns_option})
  if(ARG_STRING_CAPACITY)
    list(APPEND write_options --string-capacity ${ARG_STRING_CAPACITY})
  endif()
  if(ARG_QUEUE_CAPACITY)
    list(APPEND write_options --queue-capacity ${ARG_QUEUE_CAPACITY})
  endif()
  # Scripting enums (registerScriptingEnum): `Color=RED,GREEN,BLUE` each, and files of them.
  _btgen_flag_each(write_options --enum "${ARG_ENUMS}")
  # User port types: `Pose2D=nav::Pose2D@nav/pose2d.hpp` each.
  _btgen_flag_each(write_options --type "${ARG_TYPES}")
  _btgen_existing_files(option_files ${caller} "enums file" "${ARG_ENUM_FILES}")
  _btgen_flag_each(write_options --enums "${option_files}")
  set(read_options "${read_options}" PARENT_SCOPE)
  set(write_options "${write_options}" PARENT_SCOPE)
  set(ns_option "${ns_option}" PARENT_SCOPE)
  set(option_files "${option_files}" PARENT_SCOPE)
endfunction()

# btgen_mission_compiles(<out_var> <mission> [NAMESPACE ...] [MAIN_TREE ...] [MODELS ...]
#                        [ENUMS ...] [ENUM_FILES ...] [TYPES ...] [STRING_CAPACITY n] [QUEUE_CAPACITY n])
# True in <out_var> when the C++ back end compiles <mission> with those options (the same
# keywords as btgen_add_mission), so a mission it calls broken is one btgen_add_mission fails on.
function(btgen_mission_compiles out_var mission)
  get_property(one GLOBAL PROPERTY BTGEN_ONE_VALUE_OPTIONS)
  get_property(multi GLOBAL PROPERTY BTGEN_MULTI_VALUE_OPTIONS)
  cmake_parse_arguments(ARG "" "${one}" "${multi}" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "btgen_mission_compiles: unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  _btgen_collect_options(btgen_mission_compiles)
  _btgen_command(cmd)
  get_filename_component(mission "${mission}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  execute_process(
    COMMAND ${cmd} build-info --check "${mission}" ${read_options} ${write_options}
    OUTPUT_QUIET ERROR_QUIET
    RESULT_VARIABLE rc)
  if(rc EQUAL 0)
    set(${out_var} TRUE PARENT_SCOPE)
  else()
    set(${out_var} FALSE PARENT_SCOPE)
  endif()
endfunction()

function(btgen_add_mission)
  set(args ${ARGN})
  set(target "")
  if(args AND NOT ARGV0 STREQUAL "TARGET")
    list(GET args 0 target)  # btgen_add_mission(<target> MISSION ...)
    list(REMOVE_AT args 0)
  endif()
  get_property(one GLOBAL PROPERTY BTGEN_ONE_VALUE_OPTIONS)
  get_property(multi GLOBAL PROPERTY BTGEN_MULTI_VALUE_OPTIONS)
  cmake_parse_arguments(ARG "" "TARGET;MISSION;OUTPUT_DIR;RELATIVE_TO;SCENARIO_RUNNER;${one}" "${multi}" ${args})
  if(ARG_TARGET)
    set(target "${ARG_TARGET}")
  endif()
  if(NOT target OR NOT ARG_MISSION)
    message(FATAL_ERROR "btgen_add_mission: give a target and MISSION: btgen_add_mission(<target> MISSION <file.xml> ...)")
  endif()
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "btgen_add_mission: unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  get_property(root GLOBAL PROPERTY BTGEN_ROOT)
  _btgen_command(btgen)
  get_filename_component(mission "${ARG_MISSION}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  if(NOT EXISTS "${mission}")
    message(FATAL_ERROR "btgen_add_mission: mission ${mission} does not exist")
  endif()
  if(ARG_OUTPUT_DIR)
    get_filename_component(out_dir "${ARG_OUTPUT_DIR}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
  else()
    set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/btgen/${target}")
  endif()
  if(ARG_RELATIVE_TO)
    get_filename_component(relative_to "${ARG_RELATIVE_TO}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  else()
    set(relative_to "${CMAKE_SOURCE_DIR}")
  endif()

  # Options that change what is read (--models, --main-tree) and what is written (--namespace, capacities).
  _btgen_collect_options(btgen_add_mission)
  set(enum_files ${option_files})

  _btgen_query(deps --deps "${mission}" ${read_options} ${write_options})
  _btgen_query(names --outputs "${mission}" ${ns_option})  # also rejects a bad NAMESPACE, at configure time
  # Two missions in one namespace linked into one program share their engine and script code
  # (the linker keeps one copy of each function): mission b would run mission a's code.
  _btgen_query(template --template "${mission}" ${ns_option})
  string(REGEX REPLACE "::[^:]*$" "" mission_ns "${template}")
  # The same mission compiled for two programs (the same file, the same options: the same
  # code) may share its namespace; the generated source also defines one symbol per
  # namespace, so linking two of them into one program fails there.
  get_property(ns_owner GLOBAL PROPERTY "BTGEN_NAMESPACE_OWNER_${mission_ns}")
  get_property(ns_owner_key GLOBAL PROPERTY "BTGEN_NAMESPACE_KEY_${mission_ns}")
  set(ns_key "${mission};${read_options};${write_options}")
  if(ns_owner AND NOT ns_owner_key STREQUAL ns_key)
    message(FATAL_ERROR "btgen_add_mission: ${target} (${mission}) would generate namespace ${mission_ns}, "
      "which ${ns_owner} already uses; two missions in one namespace run each other's code when linked into "
      "one program: give one of them NAMESPACE <another>")
  endif()
  if(NOT ns_owner)
    set_property(GLOBAL PROPERTY "BTGEN_NAMESPACE_OWNER_${mission_ns}" "${target} (${mission})")
    set_property(GLOBAL PROPERTY "BTGEN_NAMESPACE_KEY_${mission_ns}" "${ns_key}")
  endif()
  _btgen_query(generator_inputs --inputs)
  if(BTGEN_EXECUTABLE)
    list(APPEND generator_inputs "${BTGEN_EXECUTABLE}")
  endif()
  # Editing the mission, an include or a models file re-runs configure, which refreshes the include list.
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${deps})

  set(outputs "")
  foreach(name IN LISTS names)
    list(APPEND outputs "${out_dir}/${name}")
  endforeach()
  list(GET names 0 header_name)
  # A dependency that goes away (a tree library's file deleted: the folder re-runs configure)
  # leaves the outputs newer than every dependency left, and the command line unchanged, so
  # no generator would run btgen again and the program would keep the deleted tree. When the
  # list of dependencies differs from the last configure's, the outputs are removed: the next
  # build runs `btgen compile`, which says what is missing (path:line:col) or regenerates.
  set(deps_record "${CMAKE_CURRENT_BINARY_DIR}/CMakeFiles/btgen/${target}.deps")
  if(EXISTS "${deps_record}")
    file(READ "${deps_record}" old_deps)
    if(NOT old_deps STREQUAL "${deps}")
      file(REMOVE ${outputs})
    endif()
  endif()
  if(NOT EXISTS "${deps_record}" OR NOT old_deps STREQUAL "${deps}")
    file(WRITE "${deps_record}" "${deps}")
  endif()

  add_custom_command(
    OUTPUT ${outputs}
    COMMAND ${btgen} compile "${mission}" -o "${out_dir}" --relative-to "${relative_to}"
            ${read_options} ${write_options}
    DEPENDS ${deps} ${enum_files} ${generator_inputs}
    WORKING_DIRECTORY "${relative_to}"
    COMMENT "btgen: generating C++ for ${ARG_MISSION}"
    VERBATIM)

  add_library(${target} STATIC ${outputs})
  target_include_directories(${target} PUBLIC "${out_dir}")
  target_link_libraries(${target} PUBLIC btgen::runtime)
  target_compile_features(${target} PUBLIC cxx_std_17)
  if(DEFINED BTGEN_WARNINGS)
    target_compile_options(${target} PRIVATE ${BTGEN_WARNINGS})
  endif()
  set_target_properties(${target} PROPERTIES
    BTGEN_HEADER "${header_name}"
    BTGEN_MISSION "${mission}")

  if(ARG_SCENARIO_RUNNER)
    add_executable(${ARG_SCENARIO_RUNNER} "${root}/runtime/src/main_driver.cpp")
    target_link_libraries(${ARG_SCENARIO_RUNNER} PRIVATE ${target} btgen::scenario)
    target_compile_definitions(${ARG_SCENARIO_RUNNER} PRIVATE
      "BTGEN_MISSION_HEADER=\"${header_name}\""
      "BTGEN_MISSION_TEMPLATE=${template}")
    if(DEFINED BTGEN_WARNINGS)
      target_compile_options(${ARG_SCENARIO_RUNNER} PRIVATE ${BTGEN_WARNINGS})
    endif()
  endif()
endfunction()
