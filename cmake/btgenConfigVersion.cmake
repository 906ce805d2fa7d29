# The version of btgen's CMake package: btgen/version.py's __version__
# (tests/python/test_package.py checks they agree). Compatible with a
# request for the same major version, no newer than this one (for 0.x, the
# same minor version).
set(PACKAGE_VERSION "0.3.0")

if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  string(REGEX MATCH "^[0-9]+\\.[0-9]+" _btgen_have "${PACKAGE_VERSION}")
  string(REGEX MATCH "^[0-9]+\\.[0-9]+" _btgen_want "${PACKAGE_FIND_VERSION}")
  if(PACKAGE_FIND_VERSION_MAJOR STREQUAL "0")
    set(_btgen_same "${_btgen_want}")
  else()
    set(_btgen_same "${PACKAGE_FIND_VERSION_MAJOR}")
    string(REGEX MATCH "^[0-9]+" _btgen_have "${PACKAGE_VERSION}")
  endif()
  if(PACKAGE_FIND_VERSION STREQUAL "" OR _btgen_have STREQUAL _btgen_same)
    set(PACKAGE_VERSION_COMPATIBLE TRUE)
  else()
    set(PACKAGE_VERSION_COMPATIBLE FALSE)
  endif()
  if(PACKAGE_FIND_VERSION STREQUAL PACKAGE_VERSION)
    set(PACKAGE_VERSION_EXACT TRUE)
  endif()
endif()
