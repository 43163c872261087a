#!/usr/bin/env python3
"""compare_reference: time per frame of pyactag against the reference package,
side by side in one process.

    python3 compare_reference.py [--frames N] [--json OUT] FRAME.pgm|DIR ...

Needs the reference implementation installed in the same environment
(``pip install actag==1.0.1 numpy matplotlib``; it imports as ``actag``,
pyactag as ``pyactag``), for this measurement only. Both run through the
same front end, ``AcTag(min_range=0.1, max_range=1.5,
horizontal_aperture=1.0472, tag_family="AcTag24h10", tag_size=0.130628571,
quads_random_seed=1).run_detection(frame)``, on the same frames, each frame
once per package after one warm-up call. Reported per frame: wall time
(perf_counter) and CPU time of the process (process_time, all threads: the
reference's Rust filters use several), and the tag IDs each one found.
"""

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import pyactag

SETTINGS = dict(min_range=0.1, max_range=1.5, horizontal_aperture=1.0472,
                tag_family="AcTag24h10", tag_size=0.130628571, quads_random_seed=1)


def frame_paths(items, limit):
    paths = []
    for item in items:
        p = Path(item)
        paths.extend(sorted(p.rglob("*.pgm")) if p.is_dir() else [p])
    return paths[:limit] if limit else paths


def timed(fn, frame):
    w, c = time.perf_counter(), time.process_time()
    out = fn(frame)
    return out, (time.perf_counter() - w) * 1e3, (time.process_time() - c) * 1e3


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("frames", nargs="+", help="PGM frames or folders of them")
    ap.add_argument("--frames", dest="limit", type=int, default=0, help="use the first N only")
    ap.add_argument("--json", help="write the per-frame figures here")
    args = ap.parse_args(argv)
    try:
        import actag as reference
    except ImportError:
        sys.stderr.write("compare_reference: the reference package is not installed "
                         "(pip install actag==1.0.1 numpy matplotlib)\n")
        return 2
    paths = frame_paths(args.frames, args.limit)
    if not paths:
        sys.stderr.write("compare_reference: no frames\n")
        return 2
    frames = [pyactag.read_pgm(p) for p in paths]
    ref = reference.AcTag(**SETTINGS)
    ours = pyactag.AcTag(**SETTINGS)
    ref.run_detection(frames[0])
    ours.run_detection(frames[0])
    rows = []
    for path, frame in zip(paths, frames):
        r_out, r_wall, r_cpu = timed(ref.run_detection, frame)
        o_out, o_wall, o_cpu = timed(ours.run_detection, frame)
        rows.append(dict(frame=path.name, reference_wall_ms=r_wall, reference_cpu_ms=r_cpu,
                         pyactag_wall_ms=o_wall, pyactag_cpu_ms=o_cpu,
                         reference_ids=[int(t[0]) for t in r_out],
                         pyactag_ids=[int(t[0]) for t in o_out]))
        print("{:24s} reference {:8.1f} ms wall {:8.1f} ms cpu {!s:8s} | pyactag {:6.2f} ms "
              "wall {:6.2f} ms cpu {!s}".format(path.name, r_wall, r_cpu, rows[-1]["reference_ids"],
                                               o_wall, o_cpu, rows[-1]["pyactag_ids"]))
        sys.stdout.flush()

    def med(key):
        return statistics.median(r[key] for r in rows)

    def mean(key):
        return statistics.mean(r[key] for r in rows)

    print()
    print("{} frames, {} with a tag from the reference, {} from pyactag".format(
        len(rows), sum(1 for r in rows if r["reference_ids"]),
        sum(1 for r in rows if r["pyactag_ids"])))
    print("time per frame      median wall   mean wall   median cpu   mean cpu")
    for name in ("reference", "pyactag"):
        print("  {:16s} {:9.1f} ms {:9.1f} ms {:9.1f} ms {:9.1f} ms".format(
            name, med(name + "_wall_ms"), mean(name + "_wall_ms"), med(name + "_cpu_ms"),
            mean(name + "_cpu_ms")))
    print("  speed-up         {:9.0f} x   {:9.0f} x   {:9.0f} x   {:9.0f} x".format(
        med("reference_wall_ms") / med("pyactag_wall_ms"),
        mean("reference_wall_ms") / mean("pyactag_wall_ms"),
        med("reference_cpu_ms") / med("pyactag_cpu_ms"),
        mean("reference_cpu_ms") / mean("pyactag_cpu_ms")))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
