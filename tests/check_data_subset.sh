#!/bin/sh
# Every file of the repository's data subset equals its original in the full
# data set (data/README.md). usage: check_data_subset.sh REPO_DATA FULL_DATA
repo=$1
full=$2
n=0
fail=0
check() { # check <file in repo_data> <file in full_data>
  n=$((n + 1))
  if ! cmp -s "$repo/$1" "$full/$2"; then
    echo "data/$1 differs from $full/$2"
    fail=1
  fi
}
check exampleSonarImage.pgm sonar/example/exampleSonarImage.pgm
for f in "$repo"/pool-video/*.pgm; do
  check "pool-video/${f##*/}" "sonar/pool-video/${f##*/}"
done
for f in "$repo"/families/*.txt; do
  check "families/${f##*/}" "families/${f##*/}"
done
[ "$n" -ge 11 ] || { echo "only $n files in $repo"; exit 1; }
[ "$fail" = 0 ] || exit 1
echo "$n files of data/ identical to their originals in $full"
