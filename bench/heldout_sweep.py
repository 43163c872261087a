#!/usr/bin/env python3
"""Held-out trust sweep: actag-eval runs of 1,000 simulated frames at seeds
nobody tuned on, each with its own random sonar, orientation, appearance and
family, so a detector rule is judged on views it was not set on.

usage: bench/heldout_sweep.py ACTAG_EVAL FIRST_SEED END_SEED [--mix any|c24h10]
       [--jobs N] [--frames N] [--eval-args "ARGS"]

--mix any (default): per seed one of the paper's sonar (1024 x 512, 0.1-5 m),
  a 530 x 512 sonar at 0.1-3.5 m with tags at 0.5-3 m, or the pool recording's
  (--pool); either orientation flag; gain, noise, beam spread, looks, clutter,
  foam, metal, mirror fraction and interference bands from the listed values;
  AcTag24h10 in 5 runs of 8, else AcTag24h8, AcTag24m10 or AcTag28m10.
--mix c24h10: AcTag24h10 on the 530 x 512 sonar only, milder appearance.

--eval-args: more actag-eval options for every run, split at spaces, so a
  detector option is judged on the same frames (--eval-args=--separate-noise:
  the = lets the value start with a dash).

Each seed's settings come from Python's random.Random(seed) (c24h10:
Random(7 seed + 1)), so a run is repeatable from its seed alone; every line
prints the settings, the right readings and the wrong IDs, false tags,
mirrored-flag and corner-order errors. A frame with an error is written to
sNNNN.fail / tNNNN.fail (actag-eval --failures) in the current folder.
Exit status 1 when any run had an error, 2 on bad arguments.
"""
import argparse
import concurrent.futures as cf
import random
import re
import subprocess
import sys

SONAR_C = ("--rows 530 --cols 512 --min-range 0.1 --max-range 3.5 "
           "--min-distance 0.5 --max-distance 3").split()


def settings_any(seed):
    r = random.Random(seed)
    base = r.choice(["paper", "C", "C", "pool"])
    a = {"paper": [], "C": SONAR_C, "pool": ["--pool"]}[base][:]
    if r.random() < 0.5:
        a.append("--range-ascending")
    if r.random() < 0.5:
        a.append("--azimuth-ascending")
    a += ["--gain", str(r.choice([130, 260, 400, 520]))]
    a += ["--noise", str(r.choice([0.0003, 0.0006, 0.0012, 0.002]))]
    a += ["--psf-azimuth", str(r.choice([0.002, 0.0035, 0.006]))]
    a += ["--psf-range", str(r.choice([0.0015, 0.0025, 0.004]))]
    a += ["--looks", str(r.choice([2, 2, 3, 4, 1]))]
    a += ["--clutter", str(r.choice([0, 4, 10, 20]))]
    a += ["--foam", str(r.choice([0.5, 1, 2]))]
    a += ["--metal-specular", str(r.choice([2, 4, 8]))]
    a += ["--mirror-fraction", str(r.choice([0.5, 1, 0]))]
    a += ["--bands", str(r.choice([0, 0, 2, 5]))]
    a += ["--family", r.choice(["AcTag24h10"] * 5 + ["AcTag24h8", "AcTag24m10", "AcTag28m10"])]
    return a, "s"


def settings_c24h10(seed):
    r = random.Random(seed * 7 + 1)
    a = SONAR_C[:]
    if r.random() < 0.5:
        a.append("--range-ascending")
    if r.random() < 0.5:
        a.append("--azimuth-ascending")
    a += ["--gain", str(r.choice([200, 260, 330]))]
    a += ["--noise", str(r.choice([0.0006, 0.001]))]
    a += ["--looks", str(r.choice([2, 3]))]
    a += ["--clutter", str(r.choice([4, 8, 12]))]
    a += ["--mirror-fraction", str(r.choice([0.5, 0.5, 1, 0]))]
    a += ["--bands", str(r.choice([0, 1, 2]))]
    return a, "t"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("eval")
    ap.add_argument("first", type=int)
    ap.add_argument("end", type=int)
    ap.add_argument("--mix", choices=["any", "c24h10"], default="any")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--frames", type=int, default=1000)
    ap.add_argument("--eval-args", default="")
    o = ap.parse_args()
    if o.end <= o.first or o.jobs < 1 or o.frames < 1:
        print("heldout_sweep: need FIRST_SEED < END_SEED, --jobs >= 1, --frames >= 1",
              file=sys.stderr)
        sys.exit(2)
    pick = settings_any if o.mix == "any" else settings_c24h10

    def run(seed):
        args, prefix = pick(seed)
        args = args + ["--seed", str(seed)] + o.eval_args.split()
        cmd = [o.eval, "--frames", str(o.frames), "--threads", "1", "--quiet",
               "--failures", f"{prefix}{seed}.fail"] + args
        p = subprocess.run(cmd, capture_output=True, text=True)
        # "detected (right ID, handedness and corner order at the tag): N = ..."
        m = re.search(r"^  detected \(right ID[^)]*\): (\d+)", p.stdout, re.M)
        errs = re.findall(r"(?:wrong IDs|false tags|mirrored-flag errors|corner-order errors): (\d+)",
                          p.stdout)
        if p.returncode != 0:
            return seed, args, None, "exit status %d: %s" % (p.returncode, p.stderr.strip())
        if not m or len(errs) != 4:
            return seed, args, None, "no detection and error counts in its output: %r" % p.stdout[:300]
        return seed, args, (int(m.group(1)), [int(e) for e in errs]), ""

    bad = 0
    with cf.ThreadPoolExecutor(o.jobs) as ex:
        for seed, args, res, err in ex.map(run, range(o.first, o.end)):
            if res is None:
                print(f"{seed} {' '.join(args)} => failed: {err}", flush=True)
                bad = 1
                continue
            right, errs = res
            bad |= any(errs)
            print(f"{seed} {' '.join(args)} => right {right}; wrong IDs, false tags, mirror, "
                  f"order errors {'/'.join(map(str, errs))}", flush=True)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
