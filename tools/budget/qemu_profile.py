#!/usr/bin/env python3
"""Cortex-M instructions per function of the budget firmware, under QEMU.

usage: qemu_profile.py [--core m4|m7] [--firmware ELF] [--top N] [--block FUNC]
                       FRAME.pgm...

Runs tools/budget's firmware (actag_budget, built by tools/budget/budget.py into
build-budget/<core>-O2) on the given pool frames under qemu-system-arm with
`-d in_asm,exec,nochain` and counts, for every translation block executed, its
guest instructions; prints the instructions per function, largest first. The
firmware runs each frame twice (actag_detect and actag_detect_inplace) and its
timer calibration spin (spin.constprop) once: divide accordingly. --block FUNC
lists that function's hottest blocks (address, executions, instructions each),
to read against `arm-none-eabi-objdump -d`. The QEMU log is large (about 1 GB a
frame) and is written to a temporary file that is removed afterwards.

Exit status 0, or 2 with a message naming the file or value that is wrong.
"""
import argparse
import collections
import os
import subprocess
import sys
import tempfile

from budget import CORES, ROOT, qemu_cmd


def die(msg):
    print("qemu_profile: " + msg, file=sys.stderr)
    sys.exit(2)


def parse(log, block):
    """Instructions per function, and per block of `block` (bytes name)."""
    size, fn_of, execs = {}, {}, collections.Counter()
    cur = None
    with open(log, "rb") as f:
        for raw in f:
            if raw.startswith(b"Trace "):
                # Trace 0: 0xHOST [flags/PC/...] symbol
                try:
                    pc = int(raw.split(b"[", 1)[1].split(b"/")[1], 16)
                except (IndexError, ValueError):
                    continue
                execs[pc] += 1
                fn_of[pc] = raw.rsplit(b" ", 1)[1].strip()
            elif raw.startswith(b"IN:"):
                cur = None
            elif raw.startswith(b"0x"):
                try:
                    pc = int(raw[2:10], 16)
                except ValueError:
                    continue
                if cur is None:
                    cur = pc
                    size[cur] = 0
                size[cur] += 1
    per_fn, blocks = collections.Counter(), []
    for pc, n in execs.items():
        ins = n * size.get(pc, 1)
        per_fn[fn_of[pc]] += ins
        if block is not None and fn_of[pc] == block:
            blocks.append((ins, pc, n, size.get(pc, 1)))
    return per_fn, sorted(blocks, reverse=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--core", default="m7")
    ap.add_argument("--firmware")
    ap.add_argument("--top", type=int, default=30)
    ap.add_argument("--block")
    ap.add_argument("frames", nargs="+")
    a = ap.parse_args()
    if a.core not in CORES:
        die("unknown --core %r (m4 or m7)" % a.core)
    if a.top < 1:
        die("--top must be at least 1, not %d" % a.top)
    fw = a.firmware or os.path.join(ROOT, "build-budget", "%s-O2" % a.core, "tools", "budget",
                                    "actag_budget")
    if not os.path.isfile(fw):
        die("no firmware %s (run tools/budget/budget.py --configs %s-O2 first)" % (fw, a.core))
    frames = [os.path.abspath(f) for f in a.frames]
    for f in frames:
        if not os.path.isfile(f):
            die("no frame %s" % f)
    if len({os.path.dirname(f) for f in frames}) != 1:
        die("the frames must share one folder (semihosting opens them by name)")
    with tempfile.TemporaryDirectory() as tmp:
        log = os.path.join(tmp, "qemu.log")
        r = subprocess.run(qemu_cmd(a.core, fw, [os.path.basename(f) for f in frames],
                                    ["-d", "in_asm,exec,nochain", "-D", log]),
                           cwd=os.path.dirname(frames[0]), capture_output=True, text=True)
        if r.returncode != 0:
            die("qemu-system-arm failed (%d): %s" % (r.returncode, r.stderr.strip()[:300]))
        for line in r.stdout.splitlines():
            if line.startswith(("frame ", "inplace ")):
                print("# " + line)
        per_fn, blocks = parse(log, a.block.encode() if a.block else None)
    total = sum(per_fn.values())
    print("# %d instructions in all" % total)
    for fn, n in per_fn.most_common(a.top):
        print("%12d %5.1f%% %s" % (n, 100.0 * n / max(total, 1), fn.decode(errors="replace")))
    if a.block:
        if not blocks:
            die("no block of function %r was executed" % a.block)
        print("# blocks of %s: instructions, address, executions, instructions each" % a.block)
        for ins, pc, n, sz in blocks[:a.top]:
            print("%12d 0x%08x %10d %4d" % (ins, pc, n, sz))


if __name__ == "__main__":
    main()
