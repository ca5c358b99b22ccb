# The consumer_find_package test: install this build into a temporary prefix, configure and
# build tests/consumer against it with find_package(lrgc) (and every installed header alone,
# LRGC_CHECK_HEADERS), and map SENA with the result (where the log is present).
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DRAWLOG=... [-DLAUNCHER=ccache]
#         -P run.cmake
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR RAWLOG)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run.cmake needs -D${v}=...")
  endif()
endforeach()

function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
step("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
file(GLOB_RECURSE config "${prefix}/lrgcConfig.cmake")
if(NOT config)
  message(FATAL_ERROR "the install into ${prefix} has no lrgcConfig.cmake")
endif()
foreach(f include/lrgc/map_builder/CMetricMapBuilderLRGC.h include/lrgc_apps/io/LogReader.h
          share/lrgc/lrgc-default.ini)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "the install into ${prefix} lacks ${f}")
  endif()
endforeach()
foreach(f include/lrgc/pose_graph/PoseGraphProblem.h include/lrgc/map_builder/TestAccess.h
          include/lrgc_apps/live include/lrgc_apps/CommandLine.h include/lrgc_apps/SlamApp.h)
  if(EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "the install holds ${f}, which is private")
  endif()
endforeach()
set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
step("configuring the consumer" ${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/consumer"
     -B "${WORK_DIR}/build" -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release ${launcher}
     -DLRGC_CHECK_HEADERS=${prefix}/include)
step("building the consumer" ${CMAKE_COMMAND} --build "${WORK_DIR}/build" --parallel 2)
# (built and its headers checked even without the log: debian_packages relies on this test
# for the build against an install)
if(NOT EXISTS "${RAWLOG}")
  message("SKIP: mapping: test data not present here: ${RAWLOG}")
  return()
endif()
step("map_rawlog" "${WORK_DIR}/build/map_rawlog" "${RAWLOG}")
message("${step_output}")
string(REGEX MATCH "keyframes ([0-9]+) scans ([0-9]+)" m "${step_output}")
if(NOT m OR CMAKE_MATCH_1 LESS 50 OR CMAKE_MATCH_2 LESS 200)
  message(FATAL_ERROR "too small a map: ${step_output}")
endif()
