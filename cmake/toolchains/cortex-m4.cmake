# Toolchain file: Cortex-M4 with single-precision FPU (FPv4-SP-D16, hard
# float ABI; e.g. STM32F4), bare metal, Debian's gcc-arm-none-eabi + newlib.
# Tests and examples run under QEMU's mps2-an386 (a Cortex-M4F board).
#   cmake -S . -B build-m4 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/cortex-m4.cmake \
#         -DACTAG_FAMILYGEN=$PWD/build/actag-familygen   (or -DACTAG_GENERATE_FAMILIES=OFF)
#   cmake --build build-m4 -j2 && ctest --test-dir build-m4
set(ACTAG_CPU_FLAGS_DEFAULT "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
set(ACTAG_QEMU_MACHINE_DEFAULT mps2-an386)
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi-gcc.cmake)
