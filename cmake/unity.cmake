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

get_filename_component(ACTAG_SHARED_DIR ${PROJECT_SOURCE_DIR}/../shared ABSOLUTE)

# actag_add_unity_test(<name> <source> [LIBS lib...])
function(actag_add_unity_test name src)
  cmake_parse_arguments(T "" "" "LIBS" ${ARGN})
  add_executable(${name} ${src})
  target_link_libraries(${name} PRIVATE actag::actag actag_unity ${T_LIBS})
  target_compile_options(${name} PRIVATE -Wall -Wextra -Wpedantic -Werror)
  target_compile_definitions(${name} PRIVATE
    ACTAG_SHARED_DIR="${ACTAG_SHARED_DIR}"
    ACTAG_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    ACTAG_BINARY_DIR="${PROJECT_BINARY_DIR}")
  if(TARGET actag-familygen)
    target_compile_definitions(${name} PRIVATE ACTAG_FAMILYGEN_PATH="$<TARGET_FILE:actag-familygen>")
    add_dependencies(${name} actag-familygen)
  endif()
  add_test(NAME ${name} COMMAND ${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  if(ACTAG_EMULATED)
    # Firmware for the QEMU board (boards/qemu-mps2), run through
    # CMAKE_CROSSCOMPILING_EMULATOR; ACTAG_TEST_EMULATED lets a test shrink
    # its random trials (test_util.h, TU_EMULATED) or IGNORE what needs the host.
    actag_board_link(${name})
    target_compile_definitions(${name} PRIVATE ACTAG_TEST_EMULATED=1)
    set_tests_properties(${name} PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77)
  endif()
endfunction()
