"""The first example of python/README.md runs and prints what the README shows
(the decision margin, which tuning of the decoder moves, is not compared)."""
import contextlib
import io
import os
import re

from conftest import REPO


def test_readme_example_output():
    text = (REPO / "python" / "README.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    shown = re.search(r"\nprints\n\n((?:    .*\n)+)", text).group(1)
    shown = [line[4:] for line in shown.splitlines()]
    out = io.StringIO()
    cwd = os.getcwd()
    try:
        os.chdir(str(REPO))
        with contextlib.redirect_stdout(out):
            exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    got = out.getvalue().splitlines()

    def strip_margin(lines):
        first = lines[0].split()
        return [" ".join(first[:2] + first[3:])] + lines[1:]

    assert strip_margin(got) == strip_margin(shown)


def test_readme_pose_example_output():
    # The "Pose from one ping" example prints what the README shows.
    text = (REPO / "python" / "README.md").read_text()
    section = text[text.index("## Pose from one ping"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    shown = re.search(r"\nprints\n\n((?:    .*\n)+)", section).group(1)
    shown = [line[4:] for line in shown.splitlines()]
    out = io.StringIO()
    cwd = os.getcwd()
    try:
        os.chdir(str(REPO))
        with contextlib.redirect_stdout(out):
            exec(compile("import pyactag\n" + code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    assert out.getvalue().splitlines() == shown
