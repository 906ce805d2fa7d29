# Installed by btgen's wheel as <prefix>/share/cmake/btgen/btgenConfig.cmake, where CMake's
# find_package(btgen) looks by itself: for every PATH entry ending in bin/ (an active virtual
# environment puts <venv>/bin there) and for every entry of CMAKE_PREFIX_PATH. So a project
# finds the btgen of the environment it is configured from without -Dbtgen_DIR.
#
# The package itself stays in site-packages (btgen/_data/cmake): this file asks the `btgen`
# command of the same prefix where that is (`btgen --cmake-dir`) and reads the package from
# there, which checks again that the command and the package belong together.

get_filename_component(_btgen_share_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT BTGEN_EXECUTABLE)
  find_program(BTGEN_EXECUTABLE NAMES btgen
    HINTS "${_btgen_share_prefix}/bin" "${_btgen_share_prefix}/Scripts"
    NO_DEFAULT_PATH)
endif()
if(NOT BTGEN_EXECUTABLE)
  set(btgen_FOUND FALSE)
  set(btgen_NOT_FOUND_MESSAGE
      "no `btgen` command in ${_btgen_share_prefix}/bin beside ${CMAKE_CURRENT_LIST_FILE}; set BTGEN_EXECUTABLE")
  return()
endif()
execute_process(COMMAND "${BTGEN_EXECUTABLE}" --cmake-dir
  OUTPUT_VARIABLE _btgen_share_dir OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_VARIABLE _btgen_share_err
  RESULT_VARIABLE _btgen_share_rc)
if(NOT _btgen_share_rc EQUAL 0 OR NOT EXISTS "${_btgen_share_dir}/btgenConfig.cmake")
  set(btgen_FOUND FALSE)
  set(btgen_NOT_FOUND_MESSAGE
      "`${BTGEN_EXECUTABLE} --cmake-dir` gave no CMake package (${_btgen_share_rc}): ${_btgen_share_err}")
  return()
endif()
include("${_btgen_share_dir}/btgenConfig.cmake")
