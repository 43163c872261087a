# actag_find_apriltag([GLOBAL]): finds AprilTag 3 with pkg-config and defines the
# interface target actag::apriltag_deps: what a program using libactag_apriltag
# links besides it -- libapriltag, and libapriltag-utils where libapriltag does
# not export the image helpers itself (Debian: its apriltag.pc gives only
# -lapriltag, and image_u8_create() & co. live in libapriltag-utils).
# Sets ACTAG_APRILTAG_UTILS (the utils library or "") in the caller's scope.
# Used by optical/CMakeLists.txt and by the installed actagConfig.cmake; leaves
# actag::apriltag_deps undefined when AprilTag 3 is not found.
function(actag_find_apriltag)
  set(global "")
  if(ARGV0 STREQUAL "GLOBAL")
    set(global GLOBAL)
  endif()
  if(TARGET actag::apriltag_deps)
    return()
  endif()
  find_package(PkgConfig QUIET)
  if(NOT PKG_CONFIG_FOUND)
    return()
  endif()
  pkg_check_modules(ACTAG_PC_APRILTAG QUIET IMPORTED_TARGET ${global} apriltag)
  if(NOT TARGET PkgConfig::ACTAG_PC_APRILTAG)
    return()
  endif()
  find_library(ACTAG_APRILTAG_UTILS_LIBRARY NAMES apriltag-utils
               HINTS ${ACTAG_PC_APRILTAG_LIBRARY_DIRS} ${ACTAG_PC_APRILTAG_LIBDIR})
  set(utils "")
  if(ACTAG_APRILTAG_UTILS_LIBRARY)
    set(utils ${ACTAG_APRILTAG_UTILS_LIBRARY})
  endif()
  add_library(actag::apriltag_deps INTERFACE IMPORTED ${global})
  set_property(TARGET actag::apriltag_deps PROPERTY
               INTERFACE_LINK_LIBRARIES PkgConfig::ACTAG_PC_APRILTAG ${utils})
  set(ACTAG_APRILTAG_UTILS "${utils}" PARENT_SCOPE)
endfunction()
