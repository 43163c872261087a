#!/bin/sh
# Instruction counts of actag_detect per frame (callgrind), the median pool
# frame, the worst adversarial frame and their ratio (issue 10: target <= 3).
# usage: bench/worst_callgrind.sh [BUILD_DIR] [worst_bench options]
# Deterministic (instructions, not time): the figure of docs/robustness.md.
set -eu
build=${1:-build}
[ $# -gt 0 ] && shift
bench=$build/bench/worst_bench
[ -x "$bench" ] || { echo "worst_callgrind: no $bench (build it first)"; exit 2; }
command -v valgrind >/dev/null || { echo "worst_callgrind: valgrind not installed"; exit 2; }
out=$(mktemp -d "${TMPDIR:-/tmp}/worst_cg.XXXXXX")
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$out/cg.out" \
         "$bench" --callgrind "$@" > "$out/bench.txt" 2> "$out/valgrind.txt" || {
  cat "$out/valgrind.txt"; exit 1; }
# every dump: "desc: Trigger: Client Request: NAME" and "summary: IR"
for f in "$out"/cg.out.*; do
  name=$(sed -n 's/^desc: Trigger: Client Request: //p' "$f")
  ir=$(sed -n 's/^summary: //p' "$f" | awk '{print $1}')
  [ -n "$name" ] && printf '%s\t%s\n' "$ir" "$name"
done | sort -t "$(printf '\t')" -k2 > "$out/ir.txt"
awk -F '\t' '
  { n++; ir[n] = $1; nm[n] = $2 }
  END {
    np = 0; worst = 0; wname = "";
    for (i = 1; i <= n; i++) {
      printf "%14.0f  %s\n", ir[i], nm[i];
      if (nm[i] ~ /^pool /) pool[++np] = ir[i];
      else if (ir[i] > worst) { worst = ir[i]; wname = nm[i] }
    }
    # median of the pool frames
    for (i = 1; i <= np; i++) for (j = i + 1; j <= np; j++) if (pool[j] < pool[i]) { t = pool[i]; pool[i] = pool[j]; pool[j] = t }
    med = np % 2 ? pool[(np + 1) / 2] : (pool[np / 2] + pool[np / 2 + 1]) / 2;
    if (np > 0)
      printf "median pool frame: %.1f M instructions (%d frames); worst adversarial: %.1f M (%s); ratio %.2f\n", med / 1e6, np, worst / 1e6, wname, worst / med;
  }' "$out/ir.txt"
