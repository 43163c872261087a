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
set(ACTAG_LINUX_TRIPLE arm-linux-gnueabihf)
set(ACTAG_LINUX_PROCESSOR arm)
set(ACTAG_LINUX_QEMU qemu-arm)
include(${CMAKE_CURRENT_LIST_DIR}/linux-gnu-cross.cmake)
