#!/bin/sh
# Detection rate and every kind of error (wrong IDs, mirrored-flag and
# corner-order errors) of each built-in family at its default corrections, on
# simulated frames at the pool recording's settings and at the paper's
# (actag-eval; docs/families.md "On simulated sonar frames: wrong IDs per family").
# usage: bench/family_trust.sh ACTAG_EVAL [FRAMES [SEED...]]   (500, seed 71)
# Prints one line per family, settings and seed; exit 1 when any run reports
# an error of any kind (the table in docs/families.md says which do).
set -eu
eval_tool=$1
frames=${2:-500}
[ $# -ge 2 ] && shift 2 || shift $#
[ $# -eq 0 ] && set -- 71
[ -x "$eval_tool" ] || { echo "family_trust: no $eval_tool (build it first)" >&2; exit 2; }
families="AcTag24h4 AcTag24h6 AcTag24h8 AcTag24h10 AcTag24m4 AcTag24m6 AcTag24m8 AcTag24m10
AcTag28m4 AcTag28m6 AcTag28m8 AcTag28m10"
fail=0
for seed in "$@"; do
  for fam in $families; do
    for settings in pool paper; do
      opt=""
      [ "$settings" = pool ] && opt="--pool"
      out=$("$eval_tool" --family "$fam" --frames "$frames" --seed "$seed" $opt --quiet --json)
      line=$(printf '%s' "$out" | python3 -c '
import json, sys
d = json.load(sys.stdin)
bad = d["wrong_ids"] + d["false_tags"] + d["mirror_errors"] + d["corner_order_errors"]
print("%d %d %d %d %d %d %d" % (d["frames"], d["detected"], d["wrong_ids"], d["false_tags"],
                                d["mirror_errors"], d["corner_order_errors"], bad))')
      read -r nframes det wrong false_tags mirror order bad <<EOF2
$line
EOF2
      printf 'family_trust: %-11s %-5s seed %s: detected %4d of %d, wrong IDs %d, false tags %d, mirror errors %d, order errors %d\n' \
        "$fam" "$settings" "$seed" "$det" "$nframes" "$wrong" "$false_tags" "$mirror" "$order"
      [ "$bad" -eq 0 ] || fail=1
    done
  done
done
exit $fail
