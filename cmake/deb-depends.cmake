# CPack reads this file before it makes a package (CPACK_PROJECT_CONFIG_FILE). For the Debian
# package it asks dpkg-shlibdeps which libraries the programs need and adds them to Depends.
#
# CPack's own CPACK_DEBIAN_PACKAGE_SHLIBDEPS runs `file` twice per installed file to find the
# programs; with the benchmark suites (3,500 files) that took 3.5 of the package's 4 minutes.
# The programs are known, so they are named here instead.
if(NOT CPACK_GENERATOR STREQUAL "DEB")
  return()
endif()
set(work "${CPACK_TOPLEVEL_DIRECTORY}/shlibdeps")
file(REMOVE_RECURSE "${work}")
file(MAKE_DIRECTORY "${work}/debian")
file(WRITE "${work}/debian/control" "")  # dpkg-shlibdeps insists on one
execute_process(COMMAND dpkg-shlibdeps -O ${CPACK_CTSFLEET_PROGRAM_FILES}
  WORKING_DIRECTORY "${work}"
  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "deb-depends.cmake: dpkg-shlibdeps failed (${result}): ${errors}")
endif()
string(REGEX REPLACE "^.*shlibs:Depends=([^\n]*).*$" "\\1" library_depends "${output}")
if(library_depends STREQUAL "" OR library_depends STREQUAL output)
  message(FATAL_ERROR "deb-depends.cmake: no shlibs:Depends in dpkg-shlibdeps' answer: ${output}")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${CPACK_DEBIAN_PACKAGE_DEPENDS}, ${library_depends}")
file(REMOVE_RECURSE "${work}")
