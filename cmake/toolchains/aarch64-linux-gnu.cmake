# Toolchain file: AArch64 Linux (Raspberry Pi 3/4/5 class, Cortex-A with
# NEON), Debian's gcc-aarch64-linux-gnu + libc6-dev-arm64-cross. Tests and
# examples run under qemu-aarch64 (qemu-user) when it is installed.
#   cmake -S . -B build-a64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DACTAG_FAMILYGEN=$PWD/build/actag-familygen   (or -DACTAG_GENERATE_FAMILIES=OFF)
#   cmake --build build-a64 -j2 && ctest --test-dir build-a64 -R "^(test_median|test_threshold|test_detect)$"
# (some of the suites .ci/linux-arm runs; the tool tests that start programs from sh
# need binfmt_misc to run the target's binaries, which containers rarely have)
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_AR aarch64-linux-gnu-ar)
set(CMAKE_NM aarch64-linux-gnu-nm)
set(CMAKE_RANLIB aarch64-linux-gnu-ranlib)

set(ACTAG_AARCH64_SYSROOT /usr/aarch64-linux-gnu CACHE PATH "Target libraries (qemu-aarch64 -L)")
find_program(ACTAG_QEMU_AARCH64 qemu-aarch64)
if(ACTAG_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${ACTAG_QEMU_AARCH64} -L ${ACTAG_AARCH64_SYSROOT})
endif()

set(CMAKE_FIND_ROOT_PATH ${ACTAG_AARCH64_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
