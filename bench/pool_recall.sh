#!/bin/sh
# Recall of tag 0 on the 58 real pool frames, in the four frame orientations the
# library supports, with no wrong ID and nothing in the tag-free frames.
# usage: bench/pool_recall.sh ACTAG_DETECT [SEED...]   (default seed 1)
# Visibility (judged once, by eye, unchanged since issue 7): tag-free frames
# 0011 0111 0211 0321 0421 0521; tag partly out of view 0331-0371 (5 frames);
# the other 47 frames show the whole tag.
# Frames are flipped with a small awk PGM rewriter so the same physical scene is
# fed in each orientation with the matching --range-ascending/--azimuth-ascending.
# Prints one line per orientation and seed; exit 1 on a wrong ID or a false tag.
# POOL_RECALL_FLAGS="--handedness mirrored" adds options to every run.
set -eu
det=$1; shift
[ $# -eq 0 ] && set -- 1
here=$(cd "$(dirname "$0")" && pwd)
pool=${ACTAG_POOL_DIR:-$here/../../shared/data/sonar/pool-video}
[ -d "$pool" ] || { echo "pool_recall: no pool frames in $pool" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
free="0011 0111 0211 0321 0421 0521"
partial="0331 0341 0351 0361 0371"
fail=0
for orient in none rows cols both; do
  mkdir -p "$tmp/$orient"
  case $orient in
    none) flags="";;
    rows) flags="--range-ascending";;
    cols) flags="--azimuth-ascending";;
    both) flags="--range-ascending --azimuth-ascending";;
  esac
  for f in "$pool"/f_*.pgm; do
    python3 "$here/flip_pgm.py" "$orient" "$f" "$tmp/$orient/$(basename "$f")"
  done
  for seed in "$@"; do
    "$det" --json --min-range 0.1 --max-range 1.5 --aperture-deg 60 --seed "$seed" \
      $flags ${POOL_RECALL_FLAGS:-} "$tmp/$orient"/f_*.pgm > "$tmp/out.json"
    python3 - "$tmp/out.json" "$orient" "$seed" "$free" "$partial" <<'PY' || fail=1
import json, sys, os
path, orient, seed, free, partial = sys.argv[1:6]
free = set(free.split()); partial = set(partial.split())
vis = found = wrong = false_tags = 0
for line in open(path):
    r = json.loads(line)
    n = os.path.basename(r["file"])[2:6]
    dets = r.get("detections", [])
    ids = [d["id"] for d in dets]
    if n in free:
        false_tags += len(dets); continue
    wrong += sum(1 for i in ids if i != 0)
    if n in partial: continue
    vis += 1
    found += 1 if 0 in ids else 0
print(f"pool_recall: orientation {orient:4s} seed {seed}: tag 0 in {found} of {vis} visible, "
      f"wrong IDs {wrong}, tags in tag-free frames {false_tags}")
sys.exit(1 if wrong or false_tags else 0)
PY
  done
done
exit $fail
