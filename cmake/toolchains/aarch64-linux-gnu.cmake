# Toolchain file: AArch64 Linux (Raspberry Pi 3/4/5 class, Cortex-A with
# NEON), Debian's gcc-aarch64-linux-gnu + libc6-dev-arm64-cross. Tests and
# examples run under qemu-aarch64 (qemu-user) when it is installed.
#   cmake -S . -B build-a64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake \
#         -DACTAG_FAMILYGEN=$PWD/build/actag-familygen   (or -DACTAG_GENERATE_FAMILIES=OFF)
#   cmake --build build-a64 -j2 && ctest --test-dir build-a64 -R "^(test_median|test_threshold|test_detect)$"
# (some of the suites .ci/linux-arm runs; the tool tests that start programs from sh
# need binfmt_misc to run the target's binaries, which containers rarely have)
set(ACTAG_LINUX_TRIPLE aarch64-linux-gnu)
set(ACTAG_LINUX_PROCESSOR aarch64)
set(ACTAG_LINUX_QEMU qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/linux-gnu-cross.cmake)
