# btgen's CMake package. In a project of your own:
#
#   pip install btgen                      # or: pip install <this checkout>
#   cmake -Dbtgen_DIR="$(btgen --cmake-dir)" ...
#
#   find_package(btgen CONFIG REQUIRED)              # or ... COMPONENTS kb
#   btgen_add_mission(my_mission MISSION mission.xml NAMESPACE robot MODELS nodes.xml)
#   target_link_libraries(my_robot PRIVATE my_mission)
#
# gives btgen_add_mission() (see btgen.cmake beside this file), the targets
# btgen::runtime (header only, C++17, no Eigen), btgen::scenario (the scenario
# harness for simulators and tests) and, when Eigen 3.3 is found,
# btgen::kb (the environment knowledge base reader; built only when linked),
# when threads are found btgen::btlog (Groot2 .btlog files) and, when cppzmq
# is found, btgen::groot2 (the Groot2 live publisher). COMPONENTS kb, btlog,
# groot2 make each required.
#
# btgen_add_mission runs the `btgen` command installed with this package,
# in BTGEN_EXECUTABLE: <prefix>/bin/btgen (Scripts\btgen.exe on Windows) of
# the environment whose site-packages holds this folder, else the `btgen` on
# PATH; either must print this folder for `btgen --cmake-dir`, so a command
# of another installation is never used. -DBTGEN_EXECUTABLE=... overrides.

get_filename_component(_btgen_pkg_dir "${CMAKE_CURRENT_LIST_DIR}" REALPATH)
get_filename_component(_btgen_data "${_btgen_pkg_dir}/.." ABSOLUTE)

# site-packages/btgen/_data/cmake -> <prefix>/bin (or <prefix>/Scripts); a checkout -> .venv/bin
get_filename_component(_btgen_prefix "${_btgen_data}/../../../../.." ABSOLUTE)
get_filename_component(_btgen_prefix_win "${_btgen_data}/../../../.." ABSOLUTE)

if(NOT BTGEN_EXECUTABLE)
  find_program(BTGEN_EXECUTABLE NAMES btgen
    HINTS "${_btgen_prefix}/bin" "${_btgen_prefix_win}/Scripts" "${_btgen_data}/.venv/bin"
    NO_DEFAULT_PATH)
  if(NOT BTGEN_EXECUTABLE)
    find_program(BTGEN_EXECUTABLE NAMES btgen)
  endif()
endif()

set(_btgen_problem "")
if(NOT BTGEN_EXECUTABLE)
  set(_btgen_problem "no `btgen` command installed with ${_btgen_pkg_dir} (looked in ${_btgen_prefix}/bin and on PATH); set BTGEN_EXECUTABLE")
else()
  execute_process(COMMAND "${BTGEN_EXECUTABLE}" --cmake-dir
    OUTPUT_VARIABLE _btgen_its_dir OUTPUT_STRIP_TRAILING_WHITESPACE
    ERROR_VARIABLE _btgen_err
    RESULT_VARIABLE _btgen_rc)
  if(NOT _btgen_rc EQUAL 0)
    set(_btgen_problem "`${BTGEN_EXECUTABLE} --cmake-dir` failed (${_btgen_rc}): ${_btgen_err}")
  else()
    get_filename_component(_btgen_its_dir "${_btgen_its_dir}" REALPATH)
    if(NOT _btgen_its_dir STREQUAL _btgen_pkg_dir)
      set(_btgen_problem "${BTGEN_EXECUTABLE} belongs to another btgen (its --cmake-dir is ${_btgen_its_dir}, not ${_btgen_pkg_dir}); set BTGEN_EXECUTABLE to the btgen installed with this package")
    endif()
  endif()
endif()

if(_btgen_problem)
  set(btgen_FOUND FALSE)
  set(btgen_NOT_FOUND_MESSAGE "${_btgen_problem}")
  return()
endif()

# Components: runtime (always there), kb (needs Eigen), btlog (needs threads)
# and groot2 (needs cppzmq).
set(btgen_runtime_FOUND TRUE)
set(_btgen_kb_required FALSE)
set(_btgen_groot2_required FALSE)
set(_btgen_btlog_required FALSE)
foreach(_btgen_component IN LISTS btgen_FIND_COMPONENTS)
  if(_btgen_component STREQUAL "kb")
    if(btgen_FIND_REQUIRED_kb)
      set(_btgen_kb_required TRUE)
    endif()
  elseif(_btgen_component STREQUAL "btlog")
    if(btgen_FIND_REQUIRED_btlog)
      set(_btgen_btlog_required TRUE)
    endif()
  elseif(_btgen_component STREQUAL "groot2")
    if(btgen_FIND_REQUIRED_groot2)
      set(_btgen_groot2_required TRUE)
    endif()
  elseif(NOT _btgen_component STREQUAL "runtime")
    set(btgen_FOUND FALSE)
    set(btgen_NOT_FOUND_MESSAGE "unknown component `${_btgen_component}` (btgen has runtime, kb, btlog and groot2)")
    return()
  endif()
endforeach()

if(NOT TARGET Eigen3::Eigen)
  find_package(Eigen3 3.3 QUIET NO_MODULE)
endif()
include("${CMAKE_CURRENT_LIST_DIR}/btgen.cmake")
_btgen_define_kb()
if(TARGET btgen_kb)
  set(btgen_kb_FOUND TRUE)
  get_target_property(_btgen_kb_dir btgen_kb SOURCE_DIR)
  if(_btgen_kb_dir STREQUAL CMAKE_CURRENT_SOURCE_DIR)
    set_target_properties(btgen_kb PROPERTIES EXCLUDE_FROM_ALL TRUE)  # built when something links it
  endif()
else()
  set(btgen_kb_FOUND FALSE)
  if(_btgen_kb_required)
    set(btgen_FOUND FALSE)
    set(btgen_NOT_FOUND_MESSAGE "component kb needs Eigen 3.3 (find_package(Eigen3 CONFIG) found none; install libeigen3-dev or set Eigen3_DIR)")
    return()
  endif()
endif()

if(NOT TARGET Threads::Threads)
  find_package(Threads QUIET)
endif()
if(NOT TARGET cppzmq)
  find_package(cppzmq QUIET)
endif()
_btgen_define_monitors()
foreach(_btgen_monitor btlog groot2)
  if(TARGET btgen_${_btgen_monitor})
    set(btgen_${_btgen_monitor}_FOUND TRUE)
  else()
    set(btgen_${_btgen_monitor}_FOUND FALSE)
    if(_btgen_${_btgen_monitor}_required)
      set(btgen_FOUND FALSE)
      if(_btgen_monitor STREQUAL "groot2")
        set(btgen_NOT_FOUND_MESSAGE "component groot2 needs ZeroMQ's C++ binding (find_package(cppzmq) found none; install libzmq3-dev and cppzmq-dev or set cppzmq_DIR)")
      else()
        set(btgen_NOT_FOUND_MESSAGE "component btlog needs threads (find_package(Threads) found none)")
      endif()
      return()
    endif()
  endif()
endforeach()

if(NOT btgen_FIND_QUIETLY)
  message(STATUS "Found btgen ${btgen_VERSION}: ${BTGEN_EXECUTABLE}")
endif()
