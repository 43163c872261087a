#!/bin/sh
# Fails when a static library references the heap or defines writable static
# data (nm classes B/b bss, D/d data, C common, G/g/S/s small data).
# usage: check_nm.sh [NM] LIBRARY
if [ $# -eq 2 ]; then NM=$1; LIB=$2; else NM=nm; LIB=$1; fi
[ -f "$LIB" ] || { echo "check_nm: no library $LIB"; exit 1; }
bad=$("$NM" "$LIB" | grep -E '^[0-9a-fA-F]* *[BbDdCGgSs] |[[:space:]]U (malloc|calloc|realloc|free)$')
heap=$("$NM" "$LIB" | grep -cE '[[:space:]]U (malloc|calloc|realloc|free)$')
writable=$("$NM" "$LIB" | grep -cE '^[0-9a-fA-F]* *[BbDdCGgSs] ')
echo "check_nm: $LIB: $heap heap references, $writable writable static symbols"
if [ -n "$bad" ]; then echo "$bad"; exit 1; fi
echo "check_nm: OK"
