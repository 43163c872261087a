# Shared part of aarch64-linux-gnu.cmake and arm-linux-gnueabihf.cmake: a
# Debian cross compiler for ARM Linux, its target libraries under
# /usr/<triple>, and qemu-user as the emulator CTest runs programs with when
# it is installed. Expects ACTAG_LINUX_TRIPLE, ACTAG_LINUX_PROCESSOR and
# ACTAG_LINUX_QEMU from the includer.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR ${ACTAG_LINUX_PROCESSOR})
set(CMAKE_C_COMPILER ${ACTAG_LINUX_TRIPLE}-gcc)
set(CMAKE_AR ${ACTAG_LINUX_TRIPLE}-ar)
set(CMAKE_NM ${ACTAG_LINUX_TRIPLE}-nm)
set(CMAKE_RANLIB ${ACTAG_LINUX_TRIPLE}-ranlib)

set(ACTAG_LINUX_SYSROOT /usr/${ACTAG_LINUX_TRIPLE} CACHE PATH "Target libraries (qemu -L)")
find_program(ACTAG_LINUX_QEMU_PATH ${ACTAG_LINUX_QEMU})
if(ACTAG_LINUX_QEMU_PATH)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${ACTAG_LINUX_QEMU_PATH} -L ${ACTAG_LINUX_SYSROOT})
endif()

set(CMAKE_FIND_ROOT_PATH ${ACTAG_LINUX_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
