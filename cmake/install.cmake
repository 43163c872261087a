# Install rules of libactag (included from the top-level CMakeLists.txt after
# the actag target; optical/CMakeLists.txt adds actag_apriltag to the same
# package). What gets installed:
#   lib/libactag.a, or libactag.so -> libactag.so.<major> -> libactag.so.<version>
#   include/actag/*.h (and the generated actag/version.h and actag/families.h)
#   lib/cmake/actag/actagConfig.cmake (+ Version, Targets): find_package(actag)
#     gives actag::actag, and actag::actag_apriltag when it was built (component
#     "apriltag": find_package(actag REQUIRED COMPONENTS apriltag))
#   lib/pkgconfig/actag.pc (and actag_apriltag.pc)
# The pkg-config files locate their prefix relative to themselves, and no
# file installed here names a library by its absolute path: dependencies are
# found again on the consumer's machine (libm by name, AprilTag by pkg-config).

set(ACTAG_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/actag)
set(ACTAG_PKGCONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Installed programs find an installed shared libactag next to them.
if(BUILD_SHARED_LIBS AND NOT DEFINED CMAKE_INSTALL_RPATH)
  file(RELATIVE_PATH _actag_bin_to_lib ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}
       ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR})
  set(CMAKE_INSTALL_RPATH "$ORIGIN/${_actag_bin_to_lib}")
endif()

install(TARGETS actag EXPORT actagTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/actag DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${ACTAG_GENERATED_INCLUDE}/actag/version.h ${ACTAG_GENERATED_INCLUDE}/actag/families.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/actag)
install(EXPORT actagTargets NAMESPACE actag:: DESTINATION ${ACTAG_CMAKE_DIR})

configure_package_config_file(cmake/actagConfig.cmake.in
  ${PROJECT_BINARY_DIR}/actagConfig.cmake INSTALL_DESTINATION ${ACTAG_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/actagConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/actagConfig.cmake ${PROJECT_BINARY_DIR}/actagConfigVersion.cmake
  DESTINATION ${ACTAG_CMAKE_DIR})

# pkg-config: ${prefix} relative to the .pc file, whatever CMAKE_INSTALL_LIBDIR
# is (lib, lib64, lib/<multiarch>).
file(RELATIVE_PATH ACTAG_PC_TO_PREFIX ${CMAKE_INSTALL_PREFIX}/${ACTAG_PKGCONFIG_DIR}
     ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" ACTAG_PC_TO_PREFIX "${ACTAG_PC_TO_PREFIX}")
set(ACTAG_PC_PREFIX "\${pcfiledir}/${ACTAG_PC_TO_PREFIX}")
# A consumer of the static library links libm itself; a shared one carries it.
set(ACTAG_PC_LIBM "")
if(NOT ACTAG_CROSS)
  set(ACTAG_PC_LIBM "-lm")
endif()
if(BUILD_SHARED_LIBS)
  set(ACTAG_PC_LIBS "-L\${libdir} -lactag")
  set(ACTAG_PC_LIBS_PRIVATE "${ACTAG_PC_LIBM}")
else()
  set(ACTAG_PC_LIBS "-L\${libdir} -lactag ${ACTAG_PC_LIBM}")
  set(ACTAG_PC_LIBS_PRIVATE "")
endif()
string(STRIP "${ACTAG_PC_LIBS}" ACTAG_PC_LIBS)
configure_file(cmake/actag.pc.in ${PROJECT_BINARY_DIR}/actag.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/actag.pc DESTINATION ${ACTAG_PKGCONFIG_DIR})

