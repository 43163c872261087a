#!/usr/bin/env bash
# Builds armcheck twice from the same armcheck.c:
#   OUT_DIR/armcheck-host  native, linked with HOST_BUILD/libactag.a
#   OUT_DIR/armcheck.elf   Cortex-M firmware (semihosting), linked with
#                          ARM_BUILD/libactag.a, for qemu-system-arm
# usage: tools/armcheck/build.sh HOST_BUILD ARM_BUILD OUT_DIR
# The CPU flags come from ARM_BUILD's CMake cache (ACTAG_CPU_FLAGS, set by
# cmake/arm-none-eabi.cmake or cmake/toolchains/cortex-m*.cmake) so the firmware
# matches the library's ABI.
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 HOST_BUILD ARM_BUILD OUT_DIR" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
host_build=$1
arm_build=$2
out=$3
mkdir -p "$out"

for lib in "$host_build/libactag.a" "$arm_build/libactag.a"; do
  [ -f "$lib" ] || { echo "armcheck: no $lib (build it first)" >&2; exit 1; }
done

cpu_flags=$(sed -n 's/^ACTAG_CPU_FLAGS:[A-Z]*=//p' "$arm_build/CMakeCache.txt" 2>/dev/null || true)
[ -n "$cpu_flags" ] || cpu_flags="-mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-sp-d16"

warn="-std=c99 -Wall -Wextra -Wpedantic -Werror -Wshadow -Wconversion"

# Host: the report is formatted by armcheck.c itself; ARMCHECK_HOST adds the
# check of its hex floats against glibc's printf("%a").
${CC:-cc} $warn -O2 -DARMCHECK_HOST -I"$root/include" -I"$host_build/include" \
  "$here/armcheck.c" "$here/io_host.c" "$host_build/libactag.a" -lm \
  -o "$out/armcheck-host"

# ARM: the QEMU board support's startup code and semihosting calls
# (boards/qemu-mps2: reset, argv from the semihosting command line, exit
# status = main's return value, faults end QEMU with status 99), armcheck's
# own semihosting I/O and memory layout (armcheck.ld: no heap, no newlib
# system calls), newlib only for memcpy/strcmp/sqrtf.
board="$root/boards/qemu-mps2"
# shellcheck disable=SC2086
arm-none-eabi-gcc $cpu_flags $warn -O2 -ffunction-sections -fdata-sections \
  -I"$root/include" -I"$arm_build/include" -I"$board" \
  "$here/armcheck.c" "$here/io_semihost.c" "$board/startup.c" \
  -nostartfiles -T "$here/armcheck.ld" -Wl,--gc-sections -Wl,-Map="$out/armcheck.map" \
  "$arm_build/libactag.a" -Wl,--start-group -lc -lm -lgcc -Wl,--end-group \
  -o "$out/armcheck.elf"
