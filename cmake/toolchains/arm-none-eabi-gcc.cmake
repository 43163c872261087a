# Shared part of cortex-m4.cmake, cortex-m7.cmake and ../arm-none-eabi.cmake (Debian's
# gcc-arm-none-eabi + libnewlib-arm-none-eabi, bare metal). Expects
# ACTAG_CPU_FLAGS_DEFAULT and ACTAG_QEMU_MACHINE_DEFAULT from the includer.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar)
set(CMAKE_NM arm-none-eabi-nm)
set(CMAKE_RANLIB arm-none-eabi-ranlib)
set(CMAKE_SIZE arm-none-eabi-size)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy)
# Compiler checks link no startup code: build a static library instead.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(ACTAG_CPU_FLAGS "${ACTAG_CPU_FLAGS_DEFAULT}" CACHE STRING "CPU flags")
set(CMAKE_C_FLAGS_INIT "${ACTAG_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,--gc-sections")

# QEMU machine of the board support (boards/qemu-mps2) the tests and
# examples link with; CTest runs them under qemu-system-arm with
# semihosting (console on QEMU's stdout, host files, exit status) when it
# is installed and a machine is named (arm-none-eabi.cmake names none).
set(ACTAG_QEMU_MACHINE "${ACTAG_QEMU_MACHINE_DEFAULT}" CACHE STRING "QEMU machine (mps2-an386, mps2-an500)")
find_program(ACTAG_QEMU_SYSTEM_ARM qemu-system-arm)
if(ACTAG_QEMU_SYSTEM_ARM AND ACTAG_QEMU_MACHINE)
  set(CMAKE_CROSSCOMPILING_EMULATOR
      ${ACTAG_QEMU_SYSTEM_ARM} -M ${ACTAG_QEMU_MACHINE} -nographic -monitor none -serial null
      -chardev stdio,id=semihost -semihosting-config enable=on,target=native,chardev=semihost
      -kernel)
endif()

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
