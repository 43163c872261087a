# Toolchain file: the library alone for a Cortex-M7 with single-precision FPU
# (FPv5-SP-D16, hard float; e.g. STM32F7), bare metal, no emulator: what
# .ci/cross and tools/armcheck build. For the tests under QEMU use
# cmake/toolchains/cortex-m4.cmake or cortex-m7.cmake.
# cmake -S . -B build-arm -DCMAKE_TOOLCHAIN_FILE=cmake/arm-none-eabi.cmake \
#       -DACTAG_FAMILYGEN=$PWD/build/actag-familygen     (or -DACTAG_GENERATE_FAMILIES=OFF)
set(ACTAG_CPU_FLAGS_DEFAULT "-mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-sp-d16")
set(ACTAG_QEMU_MACHINE_DEFAULT "") # no QEMU board: CTest runs nothing here
include(${CMAKE_CURRENT_LIST_DIR}/toolchains/arm-none-eabi-gcc.cmake)
