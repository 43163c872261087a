#!/bin/sh
# Fails when a static library references the heap or defines writable static
# data (nm classes B/b bss, D/d data, C common, G/g/S/s small data).
# usage: check_nm.sh [NM] LIBRARY
#
# Reads nm's POSIX output (-P: "name type [value size]"), so the symbol class
# is a field of its own: in the default BSD output, an address ending in a
# hex letter (...6b t name) looked like a "b" symbol to a pattern.
if [ $# -eq 2 ]; then NM=$1; LIB=$2; else NM=nm; LIB=$1; fi
[ -f "$LIB" ] || { echo "check_nm: no library $LIB"; exit 1; }
syms=$("$NM" -P "$LIB") || { echo "check_nm: $NM -P $LIB failed"; exit 1; }
heap_list=$(echo "$syms" | awk 'NF >= 2 && $2 == "U" && $1 ~ /^(malloc|calloc|realloc|free)$/')
writable_list=$(echo "$syms" | awk 'NF >= 2 && $2 ~ /^[BbDdCGgSs]$/')
heap=$(printf '%s' "$heap_list" | grep -c .)
writable=$(printf '%s' "$writable_list" | grep -c .)
echo "check_nm: $LIB: $heap heap references, $writable writable static symbols"
if [ "$heap" -ne 0 ] || [ "$writable" -ne 0 ]; then
  [ -n "$heap_list" ] && echo "$heap_list"
  [ -n "$writable_list" ] && echo "$writable_list"
  exit 1
fi
echo "check_nm: OK"
