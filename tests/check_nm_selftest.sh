#!/bin/sh
# Self-test of check_nm.sh: it must reject a real archive with writable
# statics and heap calls (BAD_LIB, built from check_nm_bad.c), and it must
# read the symbol class as a field: text symbols whose addresses end in hex
# letters (as in a sanitizer build, "16bd t fill_det") are fine, data and bss
# symbols are not, whatever their addresses.
# usage: check_nm_selftest.sh CHECK_NM_SH NM BAD_LIB
CHECK=$1; NM=$2; BAD=$3
fail() { echo "check_nm_selftest: FAIL: $*"; exit 1; }
out=$(sh "$CHECK" "$NM" "$BAD") && fail "accepted $BAD: $out"
echo "$out" | grep -q "1 heap references, 2 writable static symbols" || fail "miscounted $BAD: $out"
dir=${TMPDIR:-/tmp}/check_nm_selftest.$$
mkdir -p "$dir" || fail "no temp dir"
trap 'rm -rf "$dir"' EXIT
: > "$dir/lib.a"
# fake nm printing canned POSIX (-P) output
fake() { printf '#!/bin/sh\ncat <<"END"\n%s\nEND\n' "$1" > "$dir/nm"; chmod +x "$dir/nm"; }
fake 'lib.a[x.o]:
fill_det t 00000000000016bd 0000000000000020
same_place t 0000000000001cdd 0000000000000030
_sub_D_00099_0 t 000000000000752d 0000000000000010
actag_rng_seed T 000000000000006c 0000000000000010
.LC28 r 000000000000006d 0000000000000008
table R 00000000000000bb 0000000000000100
__asan_init U'
sh "$CHECK" "$dir/nm" "$dir/lib.a" >/dev/null || fail "rejected text/rodata symbols with hex-letter addresses"
for bad in 'counter d 0000000000000010 0000000000000004' 'zeroed b 0000000000000000 0000000000000004' \
           'shared C 0000000000000004 0000000000000004' 'small S 0000000000000000 0000000000000004' \
           'malloc U' 'free U'; do
  fake "$bad"
  sh "$CHECK" "$dir/nm" "$dir/lib.a" >/dev/null && fail "accepted '$bad'"
done
echo "check_nm_selftest: OK"
