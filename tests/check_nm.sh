#!/bin/sh
# Fails when a static library (or the object files of a shared one)
# references the heap or defines writable static data (nm classes B/b bss,
# D/d data, C common, G/g/S/s small data).
# usage: check_nm.sh [NM] LIBRARY_OR_OBJECT...   (NM when 2 or more arguments)
if [ $# -ge 2 ]; then NM=$1; shift; else NM=nm; fi
for f in "$@"; do
  [ -f "$f" ] || { echo "check_nm: no library $f"; exit 1; }
done
what=$1
[ $# -gt 1 ] && what="$# object files ($(basename "$1") ...)"
syms=$("$NM" "$@") || exit 1
bad=$(printf '%s\n' "$syms" | grep -E '^[0-9a-fA-F]* *[BbDdCGgSs] |[[:space:]]U (malloc|calloc|realloc|free)$')
heap=$(printf '%s\n' "$syms" | grep -cE '[[:space:]]U (malloc|calloc|realloc|free)$')
writable=$(printf '%s\n' "$syms" | grep -cE '^[0-9a-fA-F]* *[BbDdCGgSs] ')
echo "check_nm: $what: $heap heap references, $writable writable static symbols"
if [ -n "$bad" ]; then echo "$bad"; exit 1; fi
echo "check_nm: OK"
