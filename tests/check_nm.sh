#!/bin/sh
# Fails when a static library (or the object files of a shared one)
# references the heap or defines writable static data (nm classes B/b bss,
# D/d data, C common, G/g/S/s small data), and, with an arm-none-eabi nm (a
# firmware build), when it references libm or newlib's errno (sqrtf, logf,
# ..., __errno, _impure_ptr: they pull newlib's reentrancy data into every
# firmware; src/fpmath.h has actag_sqrtf and actag_logf instead).
# usage: check_nm.sh [NM] LIBRARY_OR_OBJECT...   (NM when 2 or more arguments)
#
# Reads nm's POSIX output (-P: "name type [value size]"), so the symbol class
# is a field of its own: in the default BSD output, an address ending in a
# hex letter (...6b t name) looked like a "b" symbol to a pattern. The
# "file:" / "lib.a[member]:" header lines nm prints for several files or
# archive members have one field and are not symbols.
if [ $# -ge 2 ]; then NM=$1; shift; else NM=nm; fi
[ $# -ge 1 ] || { echo "check_nm: usage: check_nm.sh [NM] LIBRARY_OR_OBJECT..."; exit 1; }
for f in "$@"; do
  [ -f "$f" ] || { echo "check_nm: no library $f"; exit 1; }
done
what=$1
[ $# -gt 1 ] && what="$# object files ($(basename "$1") ...)"
syms=$("$NM" -P "$@") || { echo "check_nm: $NM -P $* failed"; exit 1; }
heap_list=$(echo "$syms" | awk 'NF >= 2 && $2 == "U" && $1 ~ /^(malloc|calloc|realloc|free)$/')
writable_list=$(echo "$syms" | awk 'NF >= 2 && $2 ~ /^[BbDdCGgSs]$/')
libm_list=
case $(basename "$NM") in
  arm-*) libm_list=$(echo "$syms" | awk 'NF >= 2 && $2 == "U" && $1 ~ /^(sqrtf?|logf?|log2f?|log10f?|expf?|powf?|sinf?|cosf?|tanf?|asinf?|acosf?|atanf?|atan2f?|hypotf?|floorf?|ceilf?|roundf?|fmodf?|__errno|_impure_ptr|impure_data|errno)$/') ;;
esac
heap=$(printf '%s' "$heap_list" | grep -c .)
libm=$(printf '%s' "$libm_list" | grep -c .)
writable=$(printf '%s' "$writable_list" | grep -c .)
echo "check_nm: $what: $heap heap references, $writable writable static symbols, $libm libm/errno references"
if [ "$heap" -ne 0 ] || [ "$writable" -ne 0 ] || [ "$libm" -ne 0 ]; then
  [ -n "$heap_list" ] && echo "$heap_list"
  [ -n "$writable_list" ] && echo "$writable_list"
  [ -n "$libm_list" ] && echo "$libm_list"
  exit 1
fi
echo "check_nm: OK"
