# Toolchain file: 32-bit ARM Linux, hard float (Debian armhf: ARMv7-A with
# VFPv3-D16 and no NEON by default, so the library takes its ARMv6 SIMD /
# DSP byte-instruction paths on a Cortex-A), Debian's gcc-arm-linux-gnueabihf
# + libc6-dev-armhf-cross. Tests and examples run under qemu-arm (qemu-user)
# when it is installed.
#   cmake -S . -B build-armhf -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/arm-linux-gnueabihf.cmake \
#         -DACTAG_FAMILYGEN=$PWD/build/actag-familygen   (or -DACTAG_GENERATE_FAMILIES=OFF)
#   cmake --build build-armhf -j2 && ctest --test-dir build-armhf -R "^(test_median|test_threshold|test_detect)$"
# (some of the suites .ci/linux-arm runs; the tool tests that start programs from sh
# need binfmt_misc to run the target's binaries, which containers rarely have)
# A board with NEON: -DCMAKE_C_FLAGS="-mfpu=neon" (the NEON median then).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-linux-gnueabihf-gcc)
set(CMAKE_AR arm-linux-gnueabihf-ar)
set(CMAKE_NM arm-linux-gnueabihf-nm)
set(CMAKE_RANLIB arm-linux-gnueabihf-ranlib)

set(ACTAG_ARMHF_SYSROOT /usr/arm-linux-gnueabihf CACHE PATH "Target libraries (qemu-arm -L)")
find_program(ACTAG_QEMU_ARM qemu-arm)
if(ACTAG_QEMU_ARM)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${ACTAG_QEMU_ARM} -L ${ACTAG_ARMHF_SYSROOT})
endif()

set(CMAKE_FIND_ROOT_PATH ${ACTAG_ARMHF_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
