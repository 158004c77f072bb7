# Installation: programs in bin/, their data in share/ctsfleet/ (found relative to bin/, see
# ctsfleet/data_dir.hpp), man pages from --help (help2man), planner_core as a CMake package
# (find_package(ctsfleet) -> ctsfleet::planner_core), and a Debian package (cpack -G DEB).
include(CMakePackageConfigHelpers)

set(CTSFLEET_PROGRAMS
  ctsfleet-solve ctsfleet-gen ctsfleet-bench ctsfleet-seqbench
  ctsfleet-coordinator ctsfleet-sim ctsfleet-monitor ctsfleet-fleetbench ctsfleet-discovery
  ctsfleet-agent ctsfleet-toio-emulator ctsfleet-toio-calibrate ctsfleet-dashboard ctsfleet-task)
install(TARGETS ${CTSFLEET_PROGRAMS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The scripts as configured beside the programs (they carry the version).
install(PROGRAMS ${CMAKE_BINARY_DIR}/bin/ctsfleet-plot ${CMAKE_BINARY_DIR}/bin/ctsfleet-ca
        DESTINATION ${CMAKE_INSTALL_BINDIR})

set(CTSFLEET_DATA_DESTINATION ${CMAKE_INSTALL_DATADIR}/ctsfleet)
install(DIRECTORY config benchmarks DESTINATION ${CTSFLEET_DATA_DESTINATION})
install(FILES README.md CHANGELOG.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} PATTERN "results" EXCLUDE)
install(FILES docs/results/HISTORY.md DESTINATION ${CMAKE_INSTALL_DOCDIR}/results)  # RESULTS.md links to it
install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES cmake/debian-copyright DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)

# The Debian changelog a native package carries (the project's own history is CHANGELOG.md).
string(TIMESTAMP CTSFLEET_BUILD_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
file(WRITE ${CMAKE_BINARY_DIR}/debian/changelog
"ctsfleet (${PROJECT_VERSION}) unstable; urgency=medium

  * Release ${PROJECT_VERSION}; see /usr/share/doc/ctsfleet/CHANGELOG.md.

 -- ctsfleet developers <ctsfleet@example.org>  ${CTSFLEET_BUILD_DATE}
")
add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/debian/changelog.gz
  COMMAND gzip -9nkf ${CMAKE_BINARY_DIR}/debian/changelog
  DEPENDS ${CMAKE_BINARY_DIR}/debian/changelog)
add_custom_target(debian_changelog ALL DEPENDS ${CMAKE_BINARY_DIR}/debian/changelog.gz)
install(FILES ${CMAKE_BINARY_DIR}/debian/changelog.gz DESTINATION ${CMAKE_INSTALL_DOCDIR})

# Man pages, generated from each program's --help and --version; the NAME line from this table.
set(CTSFLEET_MAN_NAMES
  "ctsfleet-solve|plan collision-free paths for a CTS-MAPF instance or MovingAI scenario"
  "ctsfleet-gen|generate a random CTS-MAPF instance on a MovingAI map"
  "ctsfleet-bench|run solvers over benchmark instances and reproduce the experiments of the CTS-PLL paper"
  "ctsfleet-seqbench|time Held-Karp task ordering and K-best joint sequencing"
  "ctsfleet-coordinator|plan a mission and drive a robot fleet over DDS"
  "ctsfleet-sim|run a coordinator and N simulated robot agents on one host"
  "ctsfleet-monitor|check from the states of the robots that no two robots ever shared a cell"
  "ctsfleet-discovery|a Fast DDS discovery server for a fleet of many robots"
  "ctsfleet-fleetbench|measure latency, CPU and replanning time of the fleet runtime"
  "ctsfleet-agent|one robot of the fleet: a simulated robot or a toio cube over BLE"
  "ctsfleet-toio-emulator|emulated toio cubes behind a fake BlueZ on a private D-Bus"
  "ctsfleet-toio-calibrate|find toio cubes, fit and check where the grid lies on a mat"
  "ctsfleet-dashboard|the fleet live in a browser, and its runs recorded, replayed or drawn"
  "ctsfleet-task|add, cancel or list the tasks of a running fleet"
  "ctsfleet-ca|the fleet's certificate authority: enrol robots, coordinators, observers and operators for DDS Security"
  "ctsfleet-plot|draw success-rate, flowtime-ratio and anytime charts from ctsfleet-bench results")
set(CTSFLEET_SCRIPTS ctsfleet-ca ctsfleet-plot)
find_program(HELP2MAN help2man)
if(HELP2MAN)
  set(man_pages)
  foreach(entry ${CTSFLEET_MAN_NAMES})
    string(REPLACE "|" ";" entry "${entry}")
    list(GET entry 0 program)
    list(GET entry 1 man_name)
    set(page ${CMAKE_BINARY_DIR}/man/${program}.1)
    if(program IN_LIST CTSFLEET_SCRIPTS)
      set(executable ${CMAKE_BINARY_DIR}/bin/${program})
    else()
      set(executable $<TARGET_FILE:${program}>)
    endif()
    add_custom_command(OUTPUT ${page}.gz
      COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/man
      COMMAND ${HELP2MAN} --no-info --no-discard-stderr --section=1 "--name=${man_name}" --output=${page}
              ${executable}
      COMMAND gzip -9nf ${page}
      DEPENDS ${executable}
      COMMENT "man page ${program}.1"
      VERBATIM)
    list(APPEND man_pages ${page}.gz)
  endforeach()
  add_custom_target(man_pages ALL DEPENDS ${man_pages})
  install(FILES ${man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(STATUS "help2man not found: no man pages")
endif()

# planner_core for other CMake projects.
install(TARGETS planner_core ctsfleet_common EXPORT ctsfleetTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY planner_core/include/planner_core common/include/planner_core
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
set(CTSFLEET_CMAKE_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ctsfleet)
install(EXPORT ctsfleetTargets NAMESPACE ctsfleet:: DESTINATION ${CTSFLEET_CMAKE_DESTINATION})
configure_package_config_file(cmake/ctsfleetConfig.cmake.in ${CMAKE_BINARY_DIR}/ctsfleetConfig.cmake
  INSTALL_DESTINATION ${CTSFLEET_CMAKE_DESTINATION})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/ctsfleetConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/ctsfleetConfig.cmake ${CMAKE_BINARY_DIR}/ctsfleetConfigVersion.cmake
  DESTINATION ${CTSFLEET_CMAKE_DESTINATION})

# Debian package: dependencies from dpkg-shlibdeps, files under /usr.
set(CPACK_PACKAGE_NAME ctsfleet)
set(CPACK_PACKAGE_VENDOR "ctsfleet developers")
set(CPACK_PACKAGE_CONTACT "ctsfleet developers <ctsfleet@example.org>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "robot fleet planner (CTS-MAPF) and DDS fleet runtime")
set(CPACK_PACKAGE_DESCRIPTION "ctsfleet plans collision-free paths for robots that must visit tasks
and end on their goals (CTS-PLL, LaCAM, LNS), and runs the plan on a fleet of
simulated robots or toio cubes over DDS (Cyclone DDS or Fast DDS).")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# ctsfleet-plot, ctsfleet-ca, and what the CMake package (find_package(ctsfleet)) finds itself:
# yaml-cpp's CMake files and headers; the libraries the programs link from dpkg-shlibdeps, which
# cmake/deb-depends.cmake runs on the programs when the package is made.
set(CPACK_PROJECT_CONFIG_FILE ${PROJECT_SOURCE_DIR}/cmake/deb-depends.cmake)
set(CPACK_CTSFLEET_PROGRAM_FILES ${CTSFLEET_PROGRAMS})
list(TRANSFORM CPACK_CTSFLEET_PROGRAM_FILES PREPEND ${CMAKE_BINARY_DIR}/bin/)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, python3-matplotlib, openssl, libyaml-cpp-dev")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "dbus-daemon")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_STRIP_FILES ON)
set(CPACK_SOURCE_IGNORE_FILES "/build/;/\\\\.git/;/out/")
include(CPack)
