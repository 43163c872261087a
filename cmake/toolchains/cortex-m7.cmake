# Toolchain file: Cortex-M7 with double-precision FPU (FPv5-D16, hard float
# ABI; e.g. STM32H7), bare metal, Debian's gcc-arm-none-eabi + newlib.
# Tests and examples run under QEMU's mps2-an500 (a Cortex-M7 board).
#   cmake -S . -B build-m7 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/cortex-m7.cmake \
#         -DACTAG_FAMILYGEN=$PWD/build/actag-familygen   (or -DACTAG_GENERATE_FAMILIES=OFF)
#   cmake --build build-m7 -j2 && ctest --test-dir build-m7
# A single-precision-only M7 (FPv5-SP-D16): -DACTAG_CPU_FLAGS="... -mfpu=fpv5-sp-d16".
set(ACTAG_CPU_FLAGS_DEFAULT "-mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-d16")
set(ACTAG_QEMU_MACHINE_DEFAULT mps2-an500)
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-gcc.cmake)
