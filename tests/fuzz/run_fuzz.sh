#!/bin/sh
# Runs one libFuzzer harness for a bounded time on the seeds and the
# regression corpus; prints libFuzzer's final line (executions, coverage)
# and exits non-zero on any finding (the input is kept in OUT/artifacts).
# usage: tests/fuzz/run_fuzz.sh BUILD_FUZZ_DIR HARNESS SECONDS [OUT_DIR]
#   e.g. tests/fuzz/run_fuzz.sh build-fuzz detect 600 /tmp/fuzz-detect
# New inputs go to OUT_DIR/corpus (default: a temporary folder); findings to
# OUT_DIR/artifacts: copy them into tests/fuzz/corpus/HARNESS/ with the fix.
set -eu
build=$1; h=$2; secs=$3
src=$(cd "$(dirname "$0")" && pwd)
bin=$build/tests/fuzz/fuzz_$h
[ -x "$bin" ] || { echo "run_fuzz: no $bin (configure with CC=clang -DACTAG_FUZZ=ON)"; exit 2; }
if [ $# -ge 4 ]; then out=$4; keep=1; else out=$(mktemp -d "${TMPDIR:-/tmp}/fuzz_$h.XXXXXX"); keep=0; fi
mkdir -p "$out/corpus" "$out/artifacts"
dirs="$out/corpus"
[ -d "$build/fuzz-seeds/$h" ] && dirs="$dirs $build/fuzz-seeds/$h"
[ -d "$src/corpus/$h" ] && dirs="$dirs $src/corpus/$h"
max_len=4096
[ "$h" = detect ] && max_len=65536
set +e
# -rss_limit_mb: the detect harness holds frames of up to 2^18 pixels and their
# workspace; -timeout: one input may take at most 25 s (a hang is a finding).
"$bin" -max_total_time="$secs" -timeout=25 -rss_limit_mb=2048 -max_len=$max_len \
       -print_final_stats=1 -artifact_prefix="$out/artifacts/" $dirs > "$out/log.txt" 2>&1
rc=$?
set -e
grep -E '^#[0-9]+[[:space:]]+(DONE|INITED)' "$out/log.txt" | tail -2
grep -E '^Done [0-9]+ runs|stat::number_of_executed_units|stat::peak_rss_mb' "$out/log.txt" || true
if [ $rc -ne 0 ]; then
  echo "run_fuzz: $h: FINDING (status $rc); input(s) in $out/artifacts:"
  ls "$out/artifacts"
  grep -E 'fuzz check failed|runtime error|ERROR: |SUMMARY' "$out/log.txt" | head -5
  exit 1
fi
echo "run_fuzz: $h: $secs s, no finding"
[ $keep -eq 1 ] || rm -rf "$out"
