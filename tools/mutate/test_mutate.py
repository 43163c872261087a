#!/usr/bin/env python3
"""Self-test of mutate.py: its sites, its argument checks, and a whole run on
a toy CMake project where the outcome of every mutant is known.

  python3 tools/mutate/test_mutate.py   (exit 0 when every check holds)
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import mutate  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL: " + what)


def test_sites():
    text = (
        "#include <stdio.h>\n"
        "#define LIMIT (3 < 4)\n"
        "/* a < b && c */\n"
        "static const int table[4] = {\n"
        "    1, 2, 3, 4,\n"
        "};\n"
        "int f(int a, int b) { /* x > 1 */\n"
        "    const char *s = \"a < b\";\n"
        "    if (a < b && b >= 2) return a + b; // a == b\n"
        "    for (;;) { if (a != 0) break; a = a - 1; }\n"
        "    return (int)(0.5f * 2.0f) == 1;\n"
        "}\n")
    got = [(old, new, line) for _, old, new, line in mutate.sites(text, None)]
    # nothing from the preprocessor, the comments, the string or the table rows
    check(all(line >= 7 for _, _, line in got), "sites outside code: %r" % got)
    check(("<", "<=", 9) in got, "a < b not mutated")
    check(("&&", "||", 9) in got, "&& not mutated")
    check((">=", ">", 9) in got, ">= not mutated")
    check(("2", "3", 9) in got, "integer literal not mutated")
    check(("+", "-", 9) in got, "binary + not mutated")
    check(("!=", "==", 10) in got, "!= not mutated")
    check(("break;", "{}", 10) in got, "break not deleted")
    check(("-", "+", 10) in got, "binary - not mutated")
    check(("0.5f", "1.0f", 11) in got, "float literal not doubled: %r" % got)
    check(("==", "!=", 11) in got, "== not mutated")
    check(not any(old == "1" and line == 7 for old, _, line in got), "comment on line 7 mutated")
    # a comment that starts on a directive and runs on: no sites in it
    text2 = ("#define STEP 0.07f /* rad: 5 starts\n"
             "                    * (33 degrees < 40) */\n"
             "int g(int a) { return a + 5; }\n")
    got2 = [(old, new, line) for _, old, new, line in mutate.sites(text2, None)]
    check(all(line == 3 for _, _, line in got2) and ("5", "6", 3) in got2,
          "a directive's comment mutated: %r" % got2)
    only = [line for _, _, _, line in mutate.sites(text, (10, 10))]
    check(only and all(line == 10 for line in only), "--lines not honoured: %r" % only)
    # the mutated text still differs from the original at exactly the site
    for off, old, new, _ in mutate.sites(text, None):
        check(text[off:off + len(old)] == old, "site offset wrong at %d" % off)


def run_tool(args):
    p = subprocess.run([sys.executable, os.path.join(HERE, "mutate.py")] + args,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return p.returncode, p.stdout, p.stderr


def test_bad_arguments(tmp):
    rc, _, err = run_tool(["--file", "nope.c", "--tests", "x", "--build", tmp, "--source", tmp])
    check(rc == 2 and "nope.c" in err, "missing file: rc %d, %r" % (rc, err))
    open(os.path.join(tmp, "a.c"), "w").write("int x;\n")
    rc, _, err = run_tool(["--file", "a.c", "--tests", "x", "--build", tmp, "--source", tmp,
                           "--lines", "9-3"])
    check(rc == 2 and "9-3" in err, "bad --lines: rc %d, %r" % (rc, err))
    rc, _, err = run_tool(["--file", "a.c", "--tests", "(", "--build", tmp, "--source", tmp])
    check(rc == 2 and "'('" in err, "bad --tests: rc %d, %r" % (rc, err))
    rc, _, err = run_tool(["--file", "a.c", "--tests", "x", "--build", tmp, "--source", tmp,
                           "--timeout", "0"])
    check(rc == 2 and "--timeout" in err, "bad --timeout: rc %d, %r" % (rc, err))


TOY_C = """int tested(int a) {
    return a < 3;
}
int untested(int a) {
    return a + 7;
}
"""
TOY_TEST = """int tested(int a);
int untested(int a);
int main(void) {
    (void)untested;
    return !(tested(2) == 1 && tested(3) == 0);
}
"""
TOY_WIDE = """int untested(int a);
int main(void) {
    return untested(1) != 8;
}
"""
TOY_CMAKE = """cmake_minimum_required(VERSION 3.13)
project(toy C)
enable_testing()
add_executable(toy_test toy.c toy_test.c)
add_test(NAME toy_test COMMAND toy_test)
add_executable(toy_wide toy.c toy_wide.c)
add_test(NAME toy_wide COMMAND toy_wide)
"""


def test_toy_run(tmp):
    src = os.path.join(tmp, "toy")
    os.makedirs(src)
    for name, body in (("toy.c", TOY_C), ("toy_test.c", TOY_TEST), ("toy_wide.c", TOY_WIDE),
                       ("CMakeLists.txt", TOY_CMAKE)):
        with open(os.path.join(src, name), "w") as f:
            f.write(body)
    out = os.path.join(tmp, "out.json")
    rc, stdout, err = run_tool(["--source", src, "--build", os.path.join(tmp, "b"),
                                "--file", "toy.c", "--tests", "^toy_test$",
                                "--timeout", "60", "--json", out])
    check(rc == 0, "toy run failed: %d %s %s" % (rc, stdout, err))
    if rc != 0:
        return
    res = json.load(open(out))
    by = {(m["line"], m["old"], m["new"]): m["outcome"] for m in res["mutants"]}
    # a < 3: both the operator and the constant are pinned by the test
    check(by.get((2, "<", "<=")) == "killed", "a < 3 -> <= not killed: %r" % by)
    check(by.get((2, "3", "4")) == "killed", "3 -> 4 not killed: %r" % by)
    # untested(): nothing notices
    check(by.get((5, "+", "-")) == "survived", "untested + not survived: %r" % by)
    check(by.get((5, "7", "8")) == "survived", "untested 7 not survived: %r" % by)
    check(res["counts"]["killed"] == 2 and res["counts"]["survived"] == 2,
          "counts %r" % res["counts"])
    check(open(os.path.join(src, "toy.c")).read() == TOY_C, "toy.c not restored")
    check("mutation score 50.0 %" in stdout, "score line missing: %r" % stdout[-300:])
    # --confirm: the wider set (toy_wide tests untested()) kills the survivors
    rc, stdout, err = run_tool(["--source", src, "--build", os.path.join(tmp, "b"),
                                "--file", "toy.c", "--tests", "^toy_test$",
                                "--confirm", "^toy_", "--timeout", "60", "--json", out])
    check(rc == 0, "toy run with --confirm failed: %d %s %s" % (rc, stdout, err))
    if rc == 0:
        res = json.load(open(out))
        check(res["counts"]["killed"] == 4 and res["counts"]["survived"] == 0,
              "--confirm counts %r" % res["counts"])


def main():
    test_sites()
    with tempfile.TemporaryDirectory() as tmp:
        test_bad_arguments(tmp)
    with tempfile.TemporaryDirectory() as tmp:
        test_toy_run(tmp)
    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    print("mutate.py: every check holds")
    return 0


if __name__ == "__main__":
    sys.exit(main())
