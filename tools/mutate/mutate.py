#!/usr/bin/env python3
"""Mutation testing for one source file: do the tests notice a wrong line?

A test that cannot fail is a defect (DEVELOPERS.md). This script asks the
question of the tests that cover one file: it changes one operator or
constant of the file at a time (a "mutant"), rebuilds the given test
executables, runs the given CTest tests, and reports every mutant that
still passes ("survived"). A survivor is either a line no test exercises
closely enough, or an equivalent change (the same behaviour written
another way); each one needs a look.

Usage (from the repository root; the build dir is configured if empty):

  python3 tools/mutate/mutate.py --file src/family.c \
      --tests '^test_family' --build /tmp/mut/build [--sample 40] [--seed 1]
      [--lines 100-300] [--targets t1,t2] [--timeout 120] [--json OUT]

The source file is changed in place and restored after every mutant (and on
Ctrl-C), so run it in a separate worktree (`git worktree add /tmp/mut/src`)
if you keep working in this one. Exit status: 0 when it ran (survivors or
not), 2 on a bad argument or when the tests fail before any mutation.

Operators (one change per mutant, never inside comments, strings or
preprocessor lines): < <= > >= == != swapped with their neighbour
(< with <=, > with >=, == with !=), && with ||, binary + with -, an
integer literal n with n + 1 (0 with 1), a float literal x with 2x, and
the deletion of a `continue;` or `break;` (replaced by an empty block, `{}`,
so that `if (x) continue;` stays free of -Wempty-body). A build directory it
configures gets -DACTAG_WERROR=OFF (this project's option; another
project's CMake only notes it as unused), so that a mutant that merely
warns, such as `a || b && c` (-Wparentheses), is still built and run.
"""
import argparse
import json
import os
import random
import re
import signal
import subprocess
import sys
import time

REL = {"<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "=="}


def fail(msg):
    sys.stderr.write("mutate.py: " + msg + "\n")
    sys.exit(2)


def code_mask(text):
    """A list of booleans, True where text[i] is code (not comment/string/
    preprocessor line)."""
    mask = [True] * len(text)
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c in " \t":
            i += 1
            continue
        if line_start and c == "#":
            # preprocessor line, with continuations; a comment in it may
            # run on over later lines (the directive ends after it)
            j = i
            while j < n:
                if text.startswith("/*", j):
                    e = text.find("*/", j + 2)
                    j = n if e < 0 else e + 2
                    continue
                if text.startswith("//", j):
                    e = text.find("\n", j)
                    j = n if e < 0 else e
                    continue
                if text[j] == "\n" and text[j - 1] != "\\":
                    break
                j += 1
            for k in range(i, j):
                mask[k] = False
            i = j
            continue
        line_start = c == "\n"
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                mask[k] = False
            i = j
            continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            for k in range(i, j):
                mask[k] = False
            i = j
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            for k in range(i, min(j + 1, n)):
                mask[k] = False
            i = j + 1
            continue
        i += 1
    return mask


TOKEN = re.compile(
    r"(?P<float>(?<![\w.])(\d+\.\d*|\.\d+|\d+)([eE][+-]?\d+)?[fF](?!\w)"
    r"|(?<![\w.])\d+\.\d*([eE][+-]?\d+)?(?![\w.])"
    r"|(?<![\w.])\d+[eE][+-]?\d+(?![\w.]))"
    r"|(?P<int>(?<![\w.])\d+[uU]?[lL]*(?![\w.xX]))"
    r"|(?P<rel><=|>=|==|!=|(?<![<>\-])<(?![<=])|(?<![<>\-])>(?![>=]))"
    r"|(?P<logic>&&|\|\|)"
    r"|(?P<plus>(?<=[\w)\]] )[+-](?= [\w(]))"
    r"|(?P<jump>\b(?:continue|break);)")


def sites(text, lines):
    """Every (offset, old, new, line) mutation of the file."""
    mask = code_mask(text)
    out = []
    line_of = [0] * (len(text) + 1)
    ln = 1
    for i, ch in enumerate(text):
        line_of[i] = ln
        if ch == "\n":
            ln += 1
    for m in TOKEN.finditer(text):
        a = m.start()
        if not all(mask[a:m.end()]):
            continue
        line = line_of[a]
        if lines and not (lines[0] <= line <= lines[1]):
            continue
        tok = m.group(0)
        src_line = text[text.rfind("\n", 0, a) + 1:text.find("\n", a)]
        if re.fullmatch(r"[\s\w,{}()+-]*", src_line) and not re.search(r"[a-zA-Z_]\w*\s*\(|=|;", src_line):
            continue  # a row of a data table, not logic
        if m.group("float"):
            body = tok.rstrip("fF")
            try:
                v = float(body)
            except ValueError:
                continue
            new = repr(v * 2.0 if v != 0.0 else 1.0) + ("f" if tok[-1] in "fF" else "")
        elif m.group("int"):
            digits = re.match(r"\d+", tok).group(0)
            if len(digits) > 1 and digits.startswith("0"):
                continue  # octal
            if "static" in src_line and re.search(r"\[\s*" + digits + r"\s*\]", src_line):
                continue  # the size of a static table
            new = str(int(digits) + 1) + tok[len(digits):]
        elif m.group("rel"):
            new = REL[tok]
        elif m.group("logic"):
            new = "||" if tok == "&&" else "&&"
        elif m.group("plus"):
            new = "-" if tok == "+" else "+"
        elif m.group("jump"):
            new = "{}"
        else:
            continue
        out.append((a, tok, new, line))
    return out


def run(cmd, timeout):
    """(returncode or None on timeout, output tail)."""
    try:
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, start_new_session=True)
        out, _ = p.communicate(timeout=timeout)
        return p.returncode, out.decode("utf-8", "replace")[-2000:]
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return None, "timeout"


def verdict(rc):
    """A test run's return code as a mutant's outcome."""
    return "timeout" if rc is None else ("survived" if rc == 0 else "killed")


def listed(build_dir, regex, option):
    """The CTest tests of build_dir matching regex; exits when there is none."""
    rc, out = run(["ctest", "--test-dir", build_dir, "-N", "-R", regex], 60)
    names = re.findall(r"Test +#\d+: (\S+)", out)
    if not names:
        fail("%s '%s' matches no CTest test in %s" % (option, regex, build_dir))
    return names


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--file", required=True, help="source file to mutate, relative to --source")
    ap.add_argument("--tests", required=True, help="CTest -R regex of the tests that must notice")
    ap.add_argument("--build", required=True, help="build directory (configured if empty)")
    ap.add_argument("--source", default=".", help="source tree (default .)")
    ap.add_argument("--targets", default="", help="comma-separated build targets (default: the tests' names)")
    ap.add_argument("--sample", type=int, default=0, help="mutants to try, chosen at random (0: all)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--lines", default="", help="A-B: only mutate lines A..B")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per build and per test run")
    ap.add_argument("--json", default="", help="write every mutant's outcome here")
    ap.add_argument("--confirm", default="", help="CTest -R regex of a wider (slower) set that "
                    "survivors are run against before they count as survived")
    a = ap.parse_args()

    path = os.path.join(a.source, a.file)
    if not os.path.isfile(path):
        fail("no such file: %s" % path)
    lines = None
    if a.lines:
        mm = re.fullmatch(r"(\d+)-(\d+)", a.lines)
        if not mm or int(mm.group(1)) > int(mm.group(2)):
            fail("--lines wants A-B with A <= B, got '%s'" % a.lines)
        lines = (int(mm.group(1)), int(mm.group(2)))
    if a.sample < 0:
        fail("--sample must be >= 0, got %d" % a.sample)
    if a.timeout <= 0:
        fail("--timeout must be > 0, got %g" % a.timeout)
    try:
        re.compile(a.tests)
    except re.error as e:
        fail("--tests is not a regex: '%s' (%s)" % (a.tests, e))

    if not os.path.isfile(os.path.join(a.build, "CMakeCache.txt")):
        rc, out = run(["cmake", "-S", a.source, "-B", a.build,
                       "-DCMAKE_BUILD_TYPE=Release", "-DACTAG_WERROR=OFF"], a.timeout * 4)
        if rc != 0:
            fail("cannot configure %s:\n%s" % (a.build, out))
    names = listed(a.build, a.tests, "--tests")
    targets = [t for t in a.targets.split(",") if t] or names
    build = ["cmake", "--build", a.build, "-j2", "--target"] + targets
    test = ["ctest", "--test-dir", a.build, "-R", a.tests, "-j2",
            "--stop-on-failure", "--timeout", str(int(a.timeout))]
    confirm_build = confirm_test = None
    if a.confirm:
        listed(a.build, a.confirm, "--confirm")
        confirm_build = ["cmake", "--build", a.build, "-j2"]
        confirm_test = ["ctest", "--test-dir", a.build, "-R", a.confirm, "-j2",
                        "--stop-on-failure", "--timeout", str(int(a.timeout))]

    with open(path, "r", encoding="utf-8") as f:
        original = f.read()

    source_lines = original.splitlines()

    def restore(*from_signal):
        with open(path, "w", encoding="utf-8") as f:
            f.write(original)
        if from_signal:
            sys.exit(130)
    signal.signal(signal.SIGINT, restore)
    signal.signal(signal.SIGTERM, restore)

    rc, out = run(confirm_build or build, a.timeout * 8)
    if rc != 0:
        fail("the unmutated build fails:\n" + out)
    for t in [test] + ([confirm_test] if confirm_test else []):
        rc, out = run(t, a.timeout * 4)
        if rc != 0:
            fail("the tests fail before any mutation:\n" + out)

    all_sites = sites(original, lines)
    chosen = list(range(len(all_sites)))
    if a.sample and a.sample < len(chosen):
        chosen = sorted(random.Random(a.seed).sample(chosen, a.sample))
    print("%s: %d mutation sites, trying %d against %s (%s)"
          % (a.file, len(all_sites), len(chosen), a.tests, ", ".join(names)), flush=True)

    results = []
    counts = {"killed": 0, "survived": 0, "stillborn": 0, "timeout": 0}
    try:
        for k, idx in enumerate(chosen):
            off, old, new, line = all_sites[idx]
            text = original[:off] + new + original[off + len(old):]
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
            t0 = time.time()
            rc, out = run(build, a.timeout)
            if rc != 0:
                outcome = "stillborn"
            else:
                rc, out = run(test, a.timeout * 2)
                outcome = verdict(rc)
                if outcome == "survived" and confirm_test:
                    rc, out = run(confirm_build, a.timeout * 4)
                    if rc != 0:  # the rest of the tree does not build with it
                        outcome = "stillborn"
                    else:
                        rc, out = run(confirm_test, a.timeout * 4)
                        outcome = verdict(rc)
            counts[outcome] += 1
            src_line = source_lines[line - 1].strip()
            results.append({"line": line, "old": old, "new": new,
                            "outcome": outcome, "source": src_line})
            print("[%d/%d] %s:%d %s -> %s: %s (%.0f s)%s"
                  % (k + 1, len(chosen), a.file, line, old, new, outcome,
                     time.time() - t0,
                     ("\n    " + src_line) if outcome == "survived" else ""),
                  flush=True)
    finally:
        restore()
        # rebuild the original so the build dir is left as it was
        run(confirm_build or build, a.timeout * 8)

    tried = counts["killed"] + counts["survived"] + counts["timeout"]
    score = 100.0 * (counts["killed"] + counts["timeout"]) / tried if tried else 0.0
    print("%s: killed %d, timed out %d, survived %d, did not build %d; "
          "mutation score %.1f %%" % (a.file, counts["killed"], counts["timeout"],
                                      counts["survived"], counts["stillborn"], score))
    if a.json:
        with open(a.json, "w", encoding="utf-8") as f:
            json.dump({"file": a.file, "tests": a.tests, "counts": counts,
                       "score": score, "mutants": results}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
