# lrgc_discover_tests(TARGET LABEL label [RELABEL label regex]... [PROPERTIES ...])
#
# gtest_discover_tests for one test binary, every test labelled `label`, except those whose
# CTest name matches a RELABEL regex: they get that RELABEL's label instead (the first match
# wins). The labels (README.md, "Tests and benchmarks"):
#   unit      fast tests of one class or function, run in shards (lrgc_batched_tests, below)
#   e2e       the whole app or the whole builder on fixtures, Debian's SENA log, synthetic worlds
#   realdata  reads the shared benchmark logs (../shared/datasets); skips where they are absent
#   live      live mapping through MRPT's real laser drivers against an emulator (20-45 s each)
#   install   installs the build and builds a find_package(lrgc) project against it
# The tests are only known once the binary is built (and listed by ctest), so the labelling
# runs there: a file this function writes, included by ctest after the discovered tests (a
# label set there is added to the test's labels, never replaces one).
function(lrgc_discover_tests target)
  set(label "")
  set(relabels "")
  set(properties "")
  set(mode "")
  foreach(arg IN LISTS ARGN)
    if(arg STREQUAL "LABEL" OR arg STREQUAL "RELABEL" OR arg STREQUAL "PROPERTIES")
      set(mode ${arg})
    elseif(mode STREQUAL "LABEL")
      set(label ${arg})
    elseif(mode STREQUAL "RELABEL")
      list(APPEND relabels "${arg}")
    elseif(mode STREQUAL "PROPERTIES")
      list(APPEND properties "${arg}")
    endif()
  endforeach()
  list(LENGTH relabels n)
  math(EXPR odd "${n} % 2")
  if(NOT label OR odd)
    message(FATAL_ERROR "lrgc_discover_tests(${target}): needs LABEL and label/regex pairs")
  endif()

  if(properties)
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 TEST_LIST ${target}_TESTS
      PROPERTIES ${properties})
  else()
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 TEST_LIST ${target}_TESTS)
  endif()

  set(script "# Written by lrgc_discover_tests (cmake/LrgcTests.cmake): labels of ${target}.\n")
  string(APPEND script "foreach(t IN LISTS ${target}_TESTS)\n")
  set(keyword "if")
  while(relabels)
    list(POP_FRONT relabels other regex)
    # A fresh checkout has no CTest cost data, so ctest -j starts tests in the order of their
    # COST: the realdata tests (10-60 s each) first, so that none is left running alone at
    # the end.
    set(cost "")
    if(other STREQUAL "realdata")
      set(cost " COST 100")
    endif()
    string(APPEND script "  ${keyword}(t MATCHES [==[${regex}]==])\n"
      "    set_tests_properties(\"\${t}\" PROPERTIES LABELS ${other}${cost})\n")
    set(keyword "elseif")
  endwhile()
  if(keyword STREQUAL "elseif")
    string(APPEND script "  else()\n    set_tests_properties(\"\${t}\" PROPERTIES LABELS ${label})\n"
      "  endif()\n")
  else()
    string(APPEND script "  set_tests_properties(\"\${t}\" PROPERTIES LABELS ${label})\n")
  endif()
  string(APPEND script "endforeach()\n")
  set(file "${CMAKE_CURRENT_BINARY_DIR}/${target}_labels.cmake")
  file(WRITE "${file}" "${script}")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${file}")
endfunction()

# The test executables compiled as unity builds: CI builds on a fresh machine with no compiler
# cache, and each test file spends most of its compile parsing the same MRPT, Eigen and
# GoogleTest headers, so 8 test files per translation unit parse them once. Files whose
# file-local names clash with another's are compiled alone (SKIP_UNITY_BUILD_INCLUSION, listed
# per target). The libraries are unity builds too (LRGC_UNITY_LIBS, CMakeLists.txt).
option(LRGC_UNITY_TESTS "Compile the test executables 8 files per translation unit" ON)
function(lrgc_unity_tests target)
  if(NOT LRGC_UNITY_TESTS)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  # GCC warns of a fixture in an anonymous namespace "in another file": in a unity build every
  # test file is an included one.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
  foreach(f ${ARGN})
    set_source_files_properties(${f} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
  endforeach()
endfunction()

# The test executables' own code at -O1 in Release builds (CMake's -O3 stays for the libraries,
# the apps and tests/support, whose simulators and runs do the tests' computing): a test file is
# assertions and set-up, and CI compiles it cold (e2e unity_0: 49 CPU s at -O3, 34 at -O1).
# The last -O on GCC's command line wins, and target options come after CMAKE_CXX_FLAGS_RELEASE.
function(lrgc_test_code_optimization target)
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
endfunction()

# lrgc_batched_tests(TARGET LABEL label SHARDS n [SEPARATE label gtest-filter]... [PROPERTIES ...])
#
# A unit-test binary as a few CTest tests instead of one per test: every CTest test is a process,
# and starting one that links MRPT (about 300 shared libraries) costs ~0.3 CPU s, more than
# most unit tests (the three unit binaries: 39 CPU s run whole, 143 CPU s as 357 processes).
# The binary's tests run as `n` GoogleTest shards (GTEST_TOTAL_SHARDS / GTEST_SHARD_INDEX),
# CTest tests TARGET/shard_K_of_N labelled `label`; each SEPARATE filter (GoogleTest's
# --gtest_filter syntax) is one more CTest test, TARGET/LABEL, labelled with its own label and
# left out of the shards; it counts as skipped when its tests skip (e.g. no ../shared data).
# A shard's output names each test and its result; one test alone: `bin/TARGET --gtest_filter=X.y`.
function(lrgc_batched_tests target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "LABEL;SHARDS" "SEPARATE;PROPERTIES")
  list(LENGTH arg_SEPARATE n)
  math(EXPR odd "${n} % 2")
  if(NOT arg_LABEL OR NOT arg_SHARDS OR odd)
    message(FATAL_ERROR "lrgc_batched_tests(${target}): needs LABEL, SHARDS and label/filter pairs")
  endif()
  set(separated "")
  while(arg_SEPARATE)
    list(POP_FRONT arg_SEPARATE label filter)
    add_test(NAME ${target}/${label} COMMAND ${target} --gtest_filter=${filter})
    set_tests_properties(${target}/${label} PROPERTIES LABELS ${label}
      SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]" ${arg_PROPERTIES})
    string(APPEND separated ":${filter}")
  endwhile()
  set(rest "")
  if(separated)
    string(SUBSTRING "${separated}" 1 -1 separated)
    set(rest --gtest_filter=-${separated})
  endif()
  math(EXPR last "${arg_SHARDS} - 1")
  foreach(k RANGE ${last})
    set(name ${target}/shard_${k}_of_${arg_SHARDS})
    add_test(NAME ${name} COMMAND ${target} ${rest})
    set_tests_properties(${name} PROPERTIES LABELS ${arg_LABEL}
      ENVIRONMENT "GTEST_TOTAL_SHARDS=${arg_SHARDS};GTEST_SHARD_INDEX=${k}" ${arg_PROPERTIES})
  endforeach()
endfunction()
