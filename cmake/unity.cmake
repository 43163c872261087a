# Selects the Unity test framework: a real Unity when one is given
# (find_package(unity CONFIG) -> unity::framework, or -DUNITY_ROOT=<checkout>),
# otherwise the small Unity-compatible runner in tests/unity.
# Defines the target actag_unity and the function actag_add_unity_test().
if(TARGET actag_unity)
  return()
endif()
add_library(actag_unity INTERFACE)
if(UNITY_ROOT)
  if(NOT EXISTS ${UNITY_ROOT}/src/unity.c)
    message(FATAL_ERROR "UNITY_ROOT=${UNITY_ROOT} has no src/unity.c")
  endif()
  add_library(actag_unity_impl STATIC ${UNITY_ROOT}/src/unity.c)
  target_include_directories(actag_unity_impl PUBLIC ${UNITY_ROOT}/src)
  # Flush after every test so a crashing test keeps the lines before it.
  target_compile_definitions(actag_unity_impl PUBLIC UNITY_USE_FLUSH_STDOUT)
  target_link_libraries(actag_unity INTERFACE actag_unity_impl)
  message(STATUS "actag tests: Unity from ${UNITY_ROOT}")
else()
  find_package(unity CONFIG QUIET)
  if(TARGET unity::framework)
    target_link_libraries(actag_unity INTERFACE unity::framework)
    message(STATUS "actag tests: Unity package (unity::framework)")
  else()
    add_library(actag_unity_impl STATIC ${PROJECT_SOURCE_DIR}/tests/unity/unity.c)
    target_include_directories(actag_unity_impl PUBLIC ${PROJECT_SOURCE_DIR}/tests/unity)
    target_compile_options(actag_unity_impl PRIVATE ${ACTAG_WARNINGS})
    target_link_libraries(actag_unity INTERFACE actag_unity_impl)
    message(STATUS "actag tests: built-in Unity-compatible runner (tests/unity)")
  endif()
endif()

# The full data set (ACTAG_SHARED_DIR, CMakeLists.txt; ../shared by default)
# as an absolute path for the tests.
get_filename_component(ACTAG_SHARED_DIR ${ACTAG_SHARED_DIR} ABSOLUTE)

# Labels: every test is "quick" or "slow" (ctest -L quick: the whole quick set in
# about 32 s of CPU time with the full data set); tests that read the full data set in
# ${ACTAG_SHARED_DIR}/data (data/README.md) also carry "full_data".
# actag_test_labels(<test> [SLOW]) labels a test registered with add_test().
function(actag_test_labels test)
  if("SLOW" IN_LIST ARGN)
    set_property(TEST ${test} APPEND PROPERTY LABELS slow)
  else()
    set_property(TEST ${test} APPEND PROPERTY LABELS quick)
  endif()
endfunction()

# A test that needs the full data set runs its command through this prefix,
#   add_test(NAME <test> COMMAND ${ACTAG_NEEDS_FULL_DATA} cmd...)
#   actag_full_data_test(<test> [SLOW])
# and without the data CTest reports it as skipped (exit status 77 from
# tests/needs_data.sh), never as failed or passed.
set(ACTAG_NEEDS_FULL_DATA sh ${PROJECT_SOURCE_DIR}/tests/needs_data.sh ${ACTAG_SHARED_DIR}/data)
function(actag_full_data_test test)
  set_tests_properties(${test} PROPERTIES SKIP_RETURN_CODE 77)
  actag_test_labels(${test} ${ARGN})
  set_property(TEST ${test} APPEND PROPERTY LABELS full_data)
endfunction()

# actag_add_unity_test(<name> <source> [SLOW] [FULL_DATA [FULL_DATA_SLOW]] [LIBS lib...])
#   One Unity program, one CTest test <name> (label quick, or slow with SLOW).
#   FULL_DATA: the program also has tests that read the full data set, run when
#   it is called with --full-data (tests/test_util.h: tu_full_data()); they form
#   the CTest test <name>_full_data, skipped when the data is absent.
function(actag_add_unity_test name src)
  cmake_parse_arguments(T "SLOW;FULL_DATA;FULL_DATA_SLOW" "" "LIBS" ${ARGN})
  add_executable(${name} ${src})
  target_link_libraries(${name} PRIVATE actag::actag actag_unity actag_hostio ${T_LIBS})
  # -Werror as the library's ACTAG_WERROR says (on in this project's own
  # builds; tools/mutate/mutate.py turns it off so that a mutant of a source
  # file some tests compile themselves, which only warns, is still run)
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wpedantic)
  if(ACTAG_WERROR)
    target_compile_options(${name} PRIVATE -Werror)
  endif()
  target_compile_definitions(${name} PRIVATE
    ACTAG_SHARED_DIR="${ACTAG_SHARED_DIR}"
    ACTAG_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ACTAG_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(TARGET actag-familygen)
    target_compile_definitions(${name} PRIVATE ACTAG_FAMILYGEN_PATH="$<TARGET_FILE:actag-familygen>")
    add_dependencies(${name} actag-familygen)
  endif()
  add_test(NAME ${name} COMMAND ${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  if(T_SLOW)
    actag_test_labels(${name} SLOW)
  else()
    actag_test_labels(${name})
  endif()
  set(_run $<TARGET_FILE:${name}>)
  if(ACTAG_EMULATED)
    # Firmware for the QEMU board (boards/qemu-mps2), run through
    # CMAKE_CROSSCOMPILING_EMULATOR; ACTAG_TEST_EMULATED lets a test shrink
    # its random trials (test_util.h, TU_EMULATED) or IGNORE what needs the host.
    actag_board_link(${name})
    target_compile_definitions(${name} PRIVATE ACTAG_TEST_EMULATED=1)
    set_tests_properties(${name} PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77)
    # The <name>_full_data command below is not a bare target name, so CTest
    # does not add the emulator itself; --full-data reaches argv through
    # QEMU's -append (the semihosting command line, boards/qemu-mps2/startup.c).
    set(_run ${CMAKE_CROSSCOMPILING_EMULATOR} $<TARGET_FILE:${name}> -append)
  endif()
  if(T_FULL_DATA)
    add_test(NAME ${name}_full_data COMMAND ${ACTAG_NEEDS_FULL_DATA} ${_run} --full-data
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    if(T_FULL_DATA_SLOW)
      actag_full_data_test(${name}_full_data SLOW)
    else()
      actag_full_data_test(${name}_full_data)
    endif()
    if(ACTAG_EMULATED)
      set_tests_properties(${name}_full_data PROPERTIES TIMEOUT 600)
    endif()
  endif()
endfunction()
