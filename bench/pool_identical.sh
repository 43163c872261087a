#!/bin/sh
# Detections of two actag_detect builds on the same frames must be identical
# (the limits of issue 10 may not change results on real frames):
# usage: bench/pool_identical.sh BASE_ACTAG_DETECT NEW_ACTAG_DETECT [FRAME.pgm...]
# (default frames: the example frame and the 58 pool frames of ../shared).
# Compares --json output without the time_ms field; prints the verdict.
# EXTRA="--range-ascending ..." adds options to both runs (flipped frames).
set -eu
base=$1; new=$2; shift 2
if [ $# -eq 0 ]; then
  shared=$(dirname "$0")/../../shared/data/sonar
  set -- "$shared"/example/exampleSonarImage.pgm "$shared"/pool-video/f_*.pgm
fi
geo="${EXTRA:-} --min-range 0.1 --max-range 1.5 --aperture-deg 60 --family AcTag24h10 --json"
a=$(mktemp); b=$(mktemp)
trap 'rm -f "$a" "$b" "$a.raw" "$b.raw"' EXIT
# each detector's own exit status (a pipe would report sed's: two builds that
# both fail, or a missing frame, compared "identical")
detect() { # DETECTOR OUT FRAME...
  d=$1; o=$2; shift 2
  if ! "$d" $geo "$@" > "$o.raw"; then
    echo "pool_identical: FAIL: $d exited with an error" >&2
    exit 2
  fi
  sed 's/, "time_ms": [0-9.]*//' "$o.raw" > "$o"
}
detect "$base" "$a" "$@"
detect "$new" "$b" "$@"
n=$(wc -l < "$a"); tags=$(grep -o '"id": ' "$a" | wc -l)
if cmp -s "$a" "$b"; then
  echo "pool_identical: $n frames, $tags detections: identical"
else
  diff "$a" "$b" | head -20
  echo "pool_identical: FAIL: the detections differ"
  exit 1
fi
