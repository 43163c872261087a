#!/bin/sh
# A bench program's options: --help and -h print its usage on standard
# output (exit 0, nothing on standard error); an unknown option is an error
# naming the option (exit 2, nothing on standard output). With ARGS (a run
# that prints results), that run with standard output on /dev/full exits 2
# with "PROGRAM: standard output: write error" (it exited 0, results lost).
# usage: bench/check_options.sh PROGRAM [ARGS...]
set -u
prog=$1
shift
name=$(basename "$prog")
tmp=$(mktemp -d "${TMPDIR:-/tmp}/bench_options.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "check_options: $name: $*"; exit 1; }
for h in --help -h; do
  "$prog" "$h" > "$tmp/out" 2> "$tmp/err"
  st=$?
  [ "$st" -eq 0 ] || fail "$h: exit status $st, expected 0"
  head -n 1 "$tmp/out" | grep -q "^usage: $name " || fail "$h: no 'usage: $name' line on standard output"
  if [ -s "$tmp/err" ]; then fail "$h: wrote to standard error"; fi
done
"$prog" --no-such-option > "$tmp/out" 2> "$tmp/err"
st=$?
[ "$st" -eq 2 ] || fail "--no-such-option: exit status $st, expected 2"
grep -q "^$name: .*'--no-such-option'" "$tmp/err" || fail "--no-such-option: not named on standard error"
if [ -s "$tmp/out" ]; then fail "--no-such-option: wrote to standard output"; fi
if [ $# -gt 0 ] && [ -c /dev/full ]; then
  "$prog" "$@" > /dev/full 2> "$tmp/err"
  st=$?
  [ "$st" -eq 2 ] || fail "$* > /dev/full: exit status $st, expected 2"
  grep -q "^$name: standard output: write error" "$tmp/err" ||
    fail "$* > /dev/full: no write error on standard error: $(cat "$tmp/err")"
fi
echo "check_options: $name OK"
