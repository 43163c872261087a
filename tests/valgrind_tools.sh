#!/bin/sh
# Valgrind memcheck on the command-line tools (issue 10): typical runs and
# early error exits of actag_detect, actag_detect_optical, actag-render,
# actag-sim, actag-eval, actag-familygen and stage_bench must report no memory error and
# no leak ("definitely", "indirectly" or "possibly" lost), and keep their
# exit status. usage: tests/valgrind_tools.sh BUILD_DIR SOURCE_DIR
set -u
build=$1; src=$2
command -v valgrind >/dev/null 2>&1 || { echo "valgrind_tools: valgrind not installed"; exit 1; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/vg_tools.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail=0; runs=0
ex=$src/data/exampleSonarImage.pgm
geo="--min-range 0.1 --max-range 1.5 --aperture-deg 60 --family AcTag24h10"
# check EXPECTED_STATUS TOOL ARGS...
check() {
  want=$1; shift
  [ -x "$1" ] || { echo "valgrind_tools: skip $1 (not built)"; return; }
  runs=$((runs + 1))
  valgrind -q --error-exitcode=99 --leak-check=full --show-leak-kinds=definite,indirect,possible \
           --errors-for-leak-kinds=definite,indirect,possible "$@" > "$tmp/out" 2> "$tmp/err"
  st=$?
  if [ $st -ne "$want" ]; then
    echo "valgrind_tools: FAIL ($st, expected $want): $*"
    grep -E '==[0-9]+==' "$tmp/err" | head -15
    fail=1
  fi
}
d=$build/examples/actag_detect
check 0 "$d" $geo --json "$ex"
check 0 "$d" $geo --overlay "$tmp/o.ppm" --stages "$tmp/st" "$ex"
check 2 "$d" $geo "$tmp/missing.pgm"
check 2 "$d" $geo --tag-size 0 "$ex"
check 2 "$d" --bogus "$ex"
check 2 "$d" $geo
head -c 5 "$ex" > "$tmp/short.pgm"
check 2 "$d" $geo --rows 10 --cols 10 "$tmp/short.pgm" "$ex"
o=$build/examples/actag_detect_optical
printf 'P5 9 3 255\n' > "$tmp/small.pgm"; head -c 27 /dev/zero >> "$tmp/small.pgm"
check 0 "$o" --family AcTag24h10 "$tmp/small.pgm"
check 2 "$o" --family AcTag24h99 "$tmp/small.pgm"
check 2 "$o" --family AcTag24h10 "$tmp/missing.pgm"
r=$build/tools/render/actag-render
check 0 "$r" --family AcTag24h10 --id 3 --out "$tmp/t.pgm"
check 0 "$r" --family AcTag24h10 --id 3 --cut --out "$tmp/t.dxf"
check 2 "$r" --family AcTag24h4 --id 1 --cut --hole-diameter 60 --out "$tmp/h.dxf"
check 2 "$r" --family Nope --id 0
s=$build/tools/sim/actag-sim
check 0 "$s" --random 1 --rows 128 --cols 96 --out-dir "$tmp/sim"
check 2 "$s" --random 1 --rows 0 --out-dir "$tmp/sim"
# --compare-real stopped by a bad frame: it returned early without freeing
mkdir "$tmp/cmp"; printf 'P5 2 2 255\n' > "$tmp/cmp/bad.pgm"
check 2 "$s" --compare-real "$tmp/cmp" --random 1
e=$build/tools/sim/actag-eval
check 0 "$e" --frames 2 --tag-free 0 --threads 1 --quiet
check 2 "$e" --frames -1
b=$build/bench/stage_bench
# its error exits left the frames read before (a bad option after a frame,
# a 16-bit frame where 8-bit is needed) allocated
check 2 "$b" "$ex" --offset 9999
printf 'P5 2 2 65535\n' > "$tmp/w16.pgm"; head -c 8 /dev/zero >> "$tmp/w16.pgm"
check 2 "$b" "$ex" "$tmp/w16.pgm"
g=$build/actag-familygen
check 0 "$g" --bits 16 --hamming 5 --format txt --out "$tmp/f.txt"
check 2 "$g" --bits 17 --hamming 5
echo "valgrind_tools: $runs runs$([ $fail -eq 0 ] && echo ', memcheck clean')"
exit $fail
