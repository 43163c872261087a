#!/bin/sh
# Runs a test that needs the full data set (data/README.md), or reports it
# skipped: exit status 77, which CTest's SKIP_RETURN_CODE turns into "Skipped".
# usage: needs_data.sh DATA_DIR COMMAND [ARG...]
dir=$1
shift
if [ ! -d "$dir/sonar/pool-video" ]; then
  echo "SKIP: the full data set is not in $dir (data/README.md says where it comes from;" \
       "cmake -DACTAG_SHARED_DIR=<folder holding data/> points the build at it)"
  exit 77
fi
"$@"
rc=$?
# A test's own status 77 (e.g. 77 failed Unity tests) is a failure, not a skip.
[ "$rc" -eq 77 ] && rc=1
exit "$rc"
