#!/usr/bin/env python3
"""Flip a binary PGM (P5, 8 bit) for bench/pool_recall.sh.
usage: flip_pgm.py none|rows|cols|both IN.pgm OUT.pgm"""
import sys

def read_pgm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while data[pos:pos + 1] not in (b"\n", b""):
                pos += 1
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    if fields[0] != b"P5" or int(fields[3]) > 255:
        sys.exit(f"flip_pgm: {path}: not an 8-bit P5 PGM")
    cols, rows = int(fields[1]), int(fields[2])
    pix = data[pos + 1:pos + 1 + rows * cols]
    return rows, cols, [pix[r * cols:(r + 1) * cols] for r in range(rows)]

mode, src, dst = sys.argv[1:4]
rows, cols, lines = read_pgm(src)
if mode in ("rows", "both"):
    lines = lines[::-1]
if mode in ("cols", "both"):
    lines = [l[::-1] for l in lines]
with open(dst, "wb") as out:
    out.write(b"P5\n%d %d\n255\n" % (cols, rows))
    out.write(b"".join(lines))
