"""The examples of python/README.md run and print what the README shows (in
the first, the decision margin, which tuning of the decoder moves, is not
compared)."""
import contextlib
import io
import os
import re

from conftest import REPO


def readme_example(heading=None):
    """The first python example of python/README.md (after `heading`, if
    given), run in the repository in a namespace of its own: (printed
    lines, the lines its "prints" block shows or None)."""
    text = (REPO / "python" / "README.md").read_text()
    if heading:
        text = text[text.index(heading):]
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    shown = re.search(r"```\n\nprints\n\n((?:    .*\n)+)", text)
    shown = [line[4:] for line in shown.group(1).splitlines()] if shown else None
    out = io.StringIO()
    cwd = os.getcwd()
    try:
        os.chdir(str(REPO))
        with contextlib.redirect_stdout(out):
            exec(compile(code, "README.md", "exec"), {})  # each example imports what it needs
    finally:
        os.chdir(cwd)
    return out.getvalue().splitlines(), shown


def test_readme_example_output():
    got, shown = readme_example()

    def strip_margin(lines):
        first = lines[0].split()
        return [" ".join(first[:2] + first[3:])] + lines[1:]

    assert strip_margin(got) == strip_margin(shown)


def test_readme_pose_example_output():
    # The "Pose from one ping" example prints what the README shows.
    got, shown = readme_example("## Pose from one ping")
    assert got == shown


def test_readme_camera_pose_example_output():
    # The "Camera pose" example prints what the README shows.
    got, shown = readme_example("## Camera pose")
    assert got == shown


def test_readme_tracking_example_runs():
    # The "Tracking across pings" example runs on the repository's frames
    # and reports tag 0's track.
    lines, _ = readme_example("## Tracking across pings")
    assert lines and all(" track 1 tag 0 " in line for line in lines), lines
