#!/usr/bin/env python3
"""Memory and speed budget of libactag on Cortex-M4 and Cortex-M7.

For each core (M4: -mfpu=fpv4-sp-d16 on QEMU mps2-an386; M7: -mfpu=fpv5-d16
on mps2-an500) and each optimisation level (-O2, -Os) this configures and
builds a cross build (cmake/toolchains/cortex-m*.cmake, the checked-in family
tables, -fstack-usage -fcallgraph-info=su) in build-budget/<core>-<opt> and
reports:

  - .text / .rodata / .data / .bss of libactag.a without the family tables
    and per family (arm-none-eabi-size -A of the archive's members), and what
    the mcu_detect firmware (one family through its accessor, --gc-sections)
    actually links from the library;
  - the worst-case stack of actag_detect from GCC's call graph
    (-fcallgraph-info=su: every path from actag_detect, each function's
    static frame), next to the high-water mark measured on the frames;
  - the workspace bytes for 256x256, 530x512 and 1024x1024 frames, for
    actag_detect and for actag_detect_inplace (which also gets its own stack
    and instruction rows; it must find the same tags, or the script fails);
  - instructions per frame and per stage (median, search, threshold,
    contours, RANSAC, decode, other) from qemu-system-arm -icount shift=0
    runs of tools/budget/budget_fw.c over the pool frames, mean and worst,
    and the frame rate that gives at 480 MHz (STM32H7) and 168 MHz (STM32F4)
    at one instruction per cycle.

usage: tools/budget/budget.py [--frames DIR] [--configs m7-O2,m4-Os,...]
                              [--json OUT.json] [--markdown OUT.md]
  --frames   folder of the 530 x 512 pool frames (default
             ../shared/data/sonar/pool-video); every f_*.pgm in it is run
  --configs  subset of m4-O2, m4-Os, m7-O2, m7-Os (default all four)
Needs gcc-arm-none-eabi, libnewlib-arm-none-eabi, qemu-system-arm, cmake.
Prints Markdown tables (the README's budget table comes from them).
"""
import argparse
import glob
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORES = {
    "m4": ("cortex-m4.cmake", "mps2-an386"),
    "m7": ("cortex-m7.cmake", "mps2-an500"),
}
STAGES = ["median", "search", "threshold", "contours", "ransac", "decode", "refine", "other"]
# the pipeline's calls into the stages (detect.c, and readings.c for the decoders);
# each must be wrapped (tools/budget/CMakeLists.txt), or its instructions would
# silently count as "other"
PIPELINE_SOURCES = ["detect.c", "readings.c"]
STAGE_CALL = re.compile(r"\b(actag__?(?:median_filter\w*|adaptive_threshold\w*|contour_scanner_init|"
                        r"contour_next|quad_fit|decode_quad\w*|fit_rival\w*|search_map|search_next|"
                        r"refine_corners\w*))\s*\(")


def check_wrapped():
    called = set()
    for name in PIPELINE_SOURCES:
        with open(os.path.join(ROOT, "src", name)) as f:
            called |= set(STAGE_CALL.findall(f.read()))
    with open(os.path.join(ROOT, "tools", "budget", "CMakeLists.txt")) as f:
        wrapped = set(re.findall(r"\bactag_\w+", f.read()))
    missing = sorted(c for c in called if c not in wrapped)
    if missing:
        sys.exit("budget: the pipeline calls stage functions the firmware does not time: %s "
                 "(add them to tools/budget/CMakeLists.txt and budget_fw.c)" % ", ".join(missing))


def run(cmd, **kw):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    if r.returncode != 0:
        sys.exit("budget: %s failed (exit %d):\n%s" % (" ".join(cmd), r.returncode, r.stdout[-3000:]))
    return r.stdout


def build(core, opt):
    toolchain, _ = CORES[core]
    b = os.path.join(ROOT, "build-budget", "%s-%s" % (core, opt))
    run(["cmake", "-S", ROOT, "-B", b,
         "-DCMAKE_TOOLCHAIN_FILE=%s/cmake/toolchains/%s" % (ROOT, toolchain),
         "-DCMAKE_BUILD_TYPE=Release",
         "-DCMAKE_C_FLAGS_RELEASE=-%s -DNDEBUG -fstack-usage -fcallgraph-info=su" % opt,
         "-DACTAG_GENERATE_FAMILIES=OFF", "-DACTAG_BUILD_TESTS=OFF"])
    run(["cmake", "--build", b, "-j2", "--target", "actag", "actag_budget", "mcu_detect"])
    return b


def sizes(b):
    """Per archive member: text (.text*), rodata (.rodata*), data, bss."""
    out = run(["arm-none-eabi-size", "-A", os.path.join(b, "libactag.a")])
    members, cur = {}, None
    for line in out.splitlines():
        m = re.match(r"^(\S+)\s+\(ex .*\):$", line)
        if m:
            cur = members.setdefault(m.group(1), {"text": 0, "rodata": 0, "data": 0, "bss": 0})
            continue
        m = re.match(r"^(\.\S+)\s+(\d+)\s+\d+$", line)
        if m and cur is not None:
            sec, n = m.group(1), int(m.group(2))
            for key, prefix in (("text", ".text"), ("rodata", ".rodata"), ("data", ".data"),
                                ("bss", ".bss")):
                if sec == prefix or sec.startswith(prefix + "."):
                    cur[key] += n
    core = {"text": 0, "rodata": 0, "data": 0, "bss": 0}
    fams = {}
    for name, s in members.items():
        m = re.match(r"^(AcTag\w+)\.c\.obj$", name)
        if m:
            fams[m.group(1)] = s
        else:
            for k in core:
                core[k] += s[k]
    return core, fams


def linked(b):
    """Bytes of libactag.a sections kept in the mcu_detect firmware, by kind."""
    mp = open(os.path.join(b, "examples", "mcu_detect", "mcu_detect.map")).read()
    mp = mp[mp.index("Linker script and memory map"):]
    tot = {"text": 0, "rodata": 0, "data": 0, "bss": 0}
    for m in re.finditer(r"^ (\.[A-Za-z_.0-9$]+)\s+0x[0-9a-f]+\s+0x([0-9a-f]+)\s+\S*libactag\.a\(",
                         re.sub(r"\n\s{10,}", " ", mp), re.M):
        sec, n = m.group(1), int(m.group(2), 16)
        for key in tot:
            if sec == "." + key or sec.startswith("." + key + "."):
                tot[key] += n
    return tot


def stack(b):
    """Worst-case stack from actag_detect over GCC's call graph (.ci files)."""
    frames, edges, dynamic, unknown = {}, {}, set(), set()
    for ci in glob.glob(os.path.join(b, "CMakeFiles", "actag.dir", "**", "*.ci"), recursive=True):
        for line in open(ci):
            m = re.match(r'node: \{ title: "([^"]+)" label: "[^"]*\\n(\d+) bytes \(([a-z,]+)\)"', line)
            if m:
                frames[m.group(1)] = int(m.group(2))
                if m.group(3) != "static":
                    dynamic.add(m.group(1))
                continue
            m = re.match(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', line)
            if m:
                edges.setdefault(m.group(1), set()).add(m.group(2))
    memo, onpath = {}, set()

    def worst(fn):
        if fn in memo:
            return memo[fn]
        if fn in onpath:
            sys.exit("budget: recursion through %s: no static stack bound" % fn)
        if fn not in frames:
            unknown.add(fn)  # libc / libgcc leaf (memcpy, memset, __aeabi_*)
            return 0, [fn]
        onpath.add(fn)
        best, path = 0, []
        for callee in edges.get(fn, ()):
            d, p = worst(callee)
            if d > best:
                best, path = d, p
        onpath.discard(fn)
        memo[fn] = (frames[fn] + best, [fn] + path)
        return memo[fn]

    total, path = worst("actag_detect")
    total_ip, _ = worst("actag_detect_inplace")
    if dynamic:
        sys.exit("budget: functions with dynamic stack: %s" % ", ".join(sorted(dynamic)))
    return total, [p.split(":")[-1] for p in path], sorted(unknown), total_ip


def host_tags(frames_dir, names, tags):
    """The firmware must find, frame by frame, as many tags as the host build's
    actag_detect (build/examples/actag_detect, same geometry and defaults): a
    wrapper whose signature fell behind the library's would otherwise time a
    broken pipeline without a word. Skipped (with a note) without a host build."""
    det = os.path.join(ROOT, "build", "examples", "actag_detect")
    if not os.access(det, os.X_OK):
        print("budget: no host build/examples/actag_detect: tag counts not cross-checked",
              file=sys.stderr)
        return
    out = run([det, "--json", "--family", "AcTag24h10", "--min-range", "0.1", "--max-range", "1.5",
               "--aperture-deg", "60"]
              + [os.path.join(frames_dir, n) for n in names])
    host = [len(json.loads(line)["detections"]) for line in out.splitlines() if line.strip()]
    if host != tags:
        bad = [n for n, h, t in zip(names, host, tags) if h != t]
        sys.exit("budget: the firmware's tag counts differ from the host's actag_detect on %d "
                 "frames (first: %s)" % (len(bad), bad[0] if bad else "count"))


def qemu_cmd(core, fw, names, extra=()):
    """qemu-system-arm running firmware fw on core's board with -icount, its
    semihosting arguments "budget" and the frame names (opened in the cwd)."""
    _, machine = CORES[core]
    args = ",".join(["arg=budget"] + ["arg=" + n for n in names])
    return (["qemu-system-arm", "-M", machine, "-icount", "shift=0", "-nographic", "-monitor",
             "none", "-serial", "null", "-chardev", "stdio,id=sh", "-semihosting-config",
             "enable=on,target=native,chardev=sh," + args, "-kernel", fw] + list(extra))


def instructions(b, core, frames_dir):
    names = sorted(os.path.basename(f) for f in glob.glob(os.path.join(frames_dir, "f_*.pgm")))
    if not names:
        sys.exit("budget: no f_*.pgm in %s" % frames_dir)
    fw = os.path.join(b, "tools", "budget", "actag_budget")
    out = run(qemu_cmd(core, fw, names), cwd=frames_dir, timeout=3600)
    cal = re.search(r"calibration spin 10000000 measured (\d+)", out)
    if not cal or abs(int(cal.group(1)) - 10000000) > 1000:
        sys.exit("budget: the timer does not count instructions (QEMU -icount?):\n" + out[:500])
    ws = dict(re.findall(r"(\d+x\d+) (\d+)", re.search(r"^workspace .*$", out, re.M).group(0)))
    ws_ip = dict(re.findall(r"(\d+x\d+) (\d+)",
                            re.search(r"^workspace_inplace .*$", out, re.M).group(0)))
    rows, rows_ip = [], []
    for line in out.splitlines():
        if not line.startswith(("frame ", "inplace ")):
            continue
        if "unreadable" in line:
            sys.exit("budget: " + line)
        f = line.split()
        d = dict(zip(f[2::2], f[3::2]))
        (rows if f[0] == "frame" else rows_ip).append(
            {k: int(d[k]) for k in ["rows", "cols", "tags", "total", "stack"] + STAGES})
    if len(rows) != len(names) or len(rows_ip) != len(names):
        sys.exit("budget: %d and %d of %d frames reported:\n%s"
                 % (len(rows), len(rows_ip), len(names), out[-2000:]))
    if [r["tags"] for r in rows] != [r["tags"] for r in rows_ip]:
        sys.exit("budget: actag_detect_inplace found other tags than actag_detect")
    host_tags(frames_dir, names, [r["tags"] for r in rows])
    return rows, rows_ip, {k: int(v) for k, v in ws.items()}, {k: int(v) for k, v in ws_ip.items()}


def summary(rows):
    s = {}
    for k in ["total"] + STAGES:
        v = [r[k] for r in rows]
        s[k] = {"mean": sum(v) / len(v), "worst": max(v)}
    s["stack_measured"] = max(r["stack"] for r in rows)
    s["frames"] = len(rows)
    return s


def mi(x):
    return "%.1f" % (x / 1e6)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--frames", default=os.path.join(os.path.dirname(ROOT), "shared", "data", "sonar",
                                                     "pool-video"))
    ap.add_argument("--configs", default="m4-O2,m4-Os,m7-O2,m7-Os")
    ap.add_argument("--json")
    ap.add_argument("--markdown")
    a = ap.parse_args()
    check_wrapped()
    results = {}
    for cfg in a.configs.split(","):
        core, opt = cfg.split("-")
        if core not in CORES or opt not in ("O2", "Os"):
            sys.exit("budget: unknown configuration %s" % cfg)
        print("budget: %s: building" % cfg, file=sys.stderr)
        b = build(core, opt)
        core_sz, fam_sz = sizes(b)
        st, path, leaves, st_ip = stack(b)
        print("budget: %s: running the frames under QEMU -icount" % cfg, file=sys.stderr)
        rows, rows_ip, ws, ws_ip = instructions(b, core, a.frames)
        results[cfg] = {"library": core_sz, "families": fam_sz, "linked_mcu_detect": linked(b),
                        "stack_static": st, "stack_path": path, "stack_leaves_not_counted": leaves,
                        "workspace": ws, "instructions": summary(rows), "per_frame": rows,
                        "stack_static_inplace": st_ip, "workspace_inplace": ws_ip,
                        "instructions_inplace": summary(rows_ip), "per_frame_inplace": rows_ip}
    md = []
    cfgs = list(results)
    md.append("| | " + " | ".join(c.replace("-", " -") for c in cfgs) + " |")
    md.append("|---|" + "---|" * len(cfgs))

    def row(label, fn):
        md.append("| %s | %s |" % (label, " | ".join(fn(results[c]) for c in cfgs)))

    row("library .text without families (bytes)", lambda r: str(r["library"]["text"]))
    row("library .rodata without families", lambda r: str(r["library"]["rodata"]))
    row("library .data / .bss", lambda r: "%d / %d" % (r["library"]["data"], r["library"]["bss"]))
    for fam in sorted(next(iter(results.values()))["families"]):
        row("%s .text + .rodata" % fam,
            lambda r, f=fam: "%d" % (r["families"][f]["text"] + r["families"][f]["rodata"]))
    row("linked into mcu_detect (1 family): .text + .rodata",
        lambda r: "%d" % (r["linked_mcu_detect"]["text"] + r["linked_mcu_detect"]["rodata"]))
    row("actag_detect stack, call graph (bytes)", lambda r: str(r["stack_static"]))
    # measured through the timing firmware, whose wrapper of the decoder (48 bytes at -O2 on
    # the M7) lies on the deepest path: so it can exceed the library's call-graph figure
    row("actag_detect stack, measured high-water (with the timing wrapper's frame)",
        lambda r: str(r["instructions"]["stack_measured"]))
    for wsz in ("256x256", "530x512", "1024x1024"):
        row("workspace %s (bytes)" % wsz, lambda r, w=wsz: str(r["workspace"][w]))
    for k in ["total"] + STAGES:
        row("%s, M instructions per frame (mean / worst)" % k,
            lambda r, k=k: "%s / %s" % (mi(r["instructions"][k]["mean"]), mi(r["instructions"][k]["worst"])))
    # actag_detect_inplace (the filtered frame over the caller's pixels)
    for wsz in ("256x256", "530x512", "1024x1024"):
        row("actag_detect_inplace: workspace %s (bytes)" % wsz,
            lambda r, w=wsz: str(r["workspace_inplace"][w]))
    row("actag_detect_inplace: stack, call graph / measured (bytes)",
        lambda r: "%d / %d" % (r["stack_static_inplace"], r["instructions_inplace"]["stack_measured"]))
    for k in ("total", "median", "refine"):
        row("actag_detect_inplace: %s, M instructions per frame (mean / worst)" % k,
            lambda r, k=k: "%s / %s" % (mi(r["instructions_inplace"][k]["mean"]),
                                        mi(r["instructions_inplace"][k]["worst"])))
    for mhz in (480, 168):
        row("frames/s at %d MHz, 1 instr/cycle (mean / worst frame)" % mhz,
            lambda r, m=mhz: "%.1f / %.1f" % (m * 1e6 / r["instructions"]["total"]["mean"],
                                               m * 1e6 / r["instructions"]["total"]["worst"]))
    text = "\n".join(md) + "\n"
    frames = next(iter(results.values()))["instructions"]["frames"]
    text += ("\n%d pool frames of 530 x 512; stack path: %s (libc/libgcc leaves not counted: %s)\n"
             % (frames, " > ".join(next(iter(results.values()))["stack_path"]),
                ", ".join(next(iter(results.values()))["stack_leaves_not_counted"]) or "none"))
    print(text)
    if a.markdown:
        open(a.markdown, "w").write(text)
    if a.json:
        json.dump(results, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
