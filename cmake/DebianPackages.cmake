# The Debian packages, shaped as Debian's own (`cd build && cpack -G DEB`):
#   lrgc         the programs (lrgc-slam, lrgc-eval, lrgc-plot, calibrate-sweep-time),
#                share/lrgc, the man pages; runtime dependencies only, found by dpkg-shlibdeps
#                (the libraries are static: nothing of lrgc's own is shared)
#   liblrgc-dev  headers, the static libraries, the CMake package (find_package(lrgc));
#                depends on lrgc (lrgcConfig.cmake checks share/lrgc) and on the -dev packages
#                the static libraries need at link time
# Each has /usr/share/doc/<package>/copyright (machine-readable, BSD-3-Clause from LICENSE)
# and changelog.Debian.gz. Install rules without a COMPONENT fall into `dev`
# (CMAKE_INSTALL_DEFAULT_COMPONENT_NAME, set before the libraries' folders are added); the
# programs and their data are installed into `runtime` here and in apps/.
# Included from the top-level CMakeLists.txt after the targets exist.

set(LRGC_DEB_RELEASE 1)
# Set it to the packager's name and address (lintian refuses localhost and hosts without a
# dot); the default is a reserved, never-delivered domain (RFC 2606).
set(LRGC_DEB_MAINTAINER "lrgc authors <lrgc@lrgc.invalid>" CACHE STRING
  "Maintainer of the Debian packages: Name <address>")

# --- runtime: the programs' companions ---
install(PROGRAMS scripts/calibrate-sweep-time DESTINATION ${CMAKE_INSTALL_BINDIR}
  COMPONENT runtime)
# calibrate-sweep-time runs lrgc-slam through the benchmark's helpers.
install(FILES bench/bench_runs.py DESTINATION ${CMAKE_INSTALL_DATADIR}/lrgc/python
  COMPONENT runtime)

# Man pages and changelogs, gzip -9n (no name, no time stamp: reproducible), as Debian wants.
set(_deb_dir ${CMAKE_BINARY_DIR}/debian)
set(_gz_outputs)

foreach(page lrgc-slam lrgc-eval lrgc-plot calibrate-sweep-time)
  set(gz ${_deb_dir}/man/${page}.1.gz)
  file(MAKE_DIRECTORY ${_deb_dir}/man)
  add_custom_command(OUTPUT ${gz}
    COMMAND ${CMAKE_COMMAND} -E copy ${PROJECT_SOURCE_DIR}/doc/man/${page}.1 ${gz}.plain
    COMMAND gzip -9nf ${gz}.plain
    COMMAND ${CMAKE_COMMAND} -E rename ${gz}.plain.gz ${gz}
    DEPENDS ${PROJECT_SOURCE_DIR}/doc/man/${page}.1 VERBATIM)
  list(APPEND _gz_outputs ${gz})
  install(FILES ${gz} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
endforeach()

# debian/copyright (copyright-format 1.0): the licence text of LICENSE, each line indented by
# one space, empty lines as " .".
file(READ ${PROJECT_SOURCE_DIR}/LICENSE _license)
string(REGEX REPLACE "^[^\n]*\n\n[^\n]*\n[^\n]*\n\n" "" _license_body "${_license}")
string(REGEX REPLACE "\n$" "" _license_body "${_license_body}")
string(REPLACE "\n\n" "\n.\n" _license_body "${_license_body}")
string(REPLACE "\n" "\n " _license_body "${_license_body}")
file(WRITE ${_deb_dir}/copyright
  "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/\n"
  "Upstream-Name: lrgc\n"
  "\n"
  "Files: *\n"
  "Copyright: 2026 the lrgc authors\n"
  "License: BSD-3-Clause\n"
  " ${_license_body}\n")

if(DEFINED ENV{SOURCE_DATE_EPOCH})
  string(TIMESTAMP _deb_date "%a, %d %b %Y %H:%M:%S +0000" UTC)
else()
  string(TIMESTAMP _deb_date "%a, %d %b %Y 00:00:00 +0000" UTC)
endif()
foreach(pkg lrgc liblrgc-dev)
  set(component runtime)
  if(pkg STREQUAL "liblrgc-dev")
    set(component dev)
  endif()
  file(WRITE ${_deb_dir}/${pkg}/changelog.Debian
    "${pkg} (${PROJECT_VERSION}-${LRGC_DEB_RELEASE}) unstable; urgency=medium\n\n"
    "  * Built by CPack from the lrgc sources, version ${PROJECT_VERSION}.\n\n"
    " -- ${LRGC_DEB_MAINTAINER}  ${_deb_date}\n")
  set(gz ${_deb_dir}/${pkg}/changelog.Debian.gz)
  add_custom_command(OUTPUT ${gz}
    COMMAND ${CMAKE_COMMAND} -E copy ${_deb_dir}/${pkg}/changelog.Debian ${gz}.plain
    COMMAND gzip -9nf ${gz}.plain
    COMMAND ${CMAKE_COMMAND} -E rename ${gz}.plain.gz ${gz}
    DEPENDS ${_deb_dir}/${pkg}/changelog.Debian VERBATIM)
  list(APPEND _gz_outputs ${gz})
  install(FILES ${_deb_dir}/copyright ${gz}
    DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${pkg} COMPONENT ${component})
endforeach()
add_custom_target(lrgc_debian_files ALL DEPENDS ${_gz_outputs})

# --- CPack ---
set(CPACK_PACKAGE_NAME lrgc)
set(CPACK_PACKAGE_VENDOR "the lrgc authors")
set(CPACK_PACKAGE_CONTACT "${LRGC_DEB_MAINTAINER}")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_RELEASE ${LRGC_DEB_RELEASE})
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://www.mrpt.org/")
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME lrgc)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION science)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# calibrate-sweep-time is Python and times its runs with /usr/bin/time.
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "python3, time")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "mrpt-apps")
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
  "2D laser SLAM for MRPT by local registration and global correlation
lrgc-slam maps MRPT rawlogs and CARMEN logs (and live mrpt::hwdrivers
lasers) into occupancy grids, pose graphs and trajectories, closing loops
by global correlation (Gutmann and Konolige, 1999). It runs icp-slam .ini
files and writes ready pf-localization and observations2map .ini files.

This package holds the programs lrgc-slam, lrgc-eval, lrgc-plot and
calibrate-sweep-time, and the default parameter files.")

set(CPACK_DEBIAN_DEV_PACKAGE_NAME liblrgc-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
  "lrgc (= ${PROJECT_VERSION}-${LRGC_DEB_RELEASE}), libmrpt-dev (>= 2.5), libeigen3-dev, libopencv-dev, libsuitesparse-dev")
set(CPACK_COMPONENT_DEV_DESCRIPTION
  "development files of lrgc, 2D laser SLAM for MRPT
lrgc::CMetricMapBuilderLRGC is an mrpt::slam::CMetricMapBuilder that maps
with local registration and global correlation (Gutmann and Konolige,
1999); lrgc::lrgc_apps holds log readers, outputs and evaluation.

This package holds the headers, the static libraries and the CMake
package: find_package(lrgc) gives lrgc::lrgc and lrgc::lrgc_apps.")

include(CPack)
