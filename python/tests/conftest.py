"""Shared fixtures: repository paths, frames, the C tool's JSON output.

Environment:
  ACTAG_DATA_DIR  the real data (default: <repo>/../shared/data); tests that
                  need the pool frames skip visibly when it is absent.
  ACTAG_DETECT    the C tool actag_detect (default: <repo>/build/examples/
                  actag_detect); when set it must exist, otherwise the
                  comparisons with it skip visibly when it is not built.
"""
import json
import os
import subprocess
from pathlib import Path

import pytest

import pyactag

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "data" / "exampleSonarImage.pgm"
DATA = Path(os.environ.get("ACTAG_DATA_DIR", REPO.parent / "shared" / "data"))
POOL = DATA / "sonar" / "pool-video"

# The sonar of every frame in the repository and in the pool recording.
GEOMETRY = dict(min_range=0.1, max_range=1.5, aperture_deg=60.0)
FAMILY = "AcTag24h10"
TAG_SIZE = 0.130628571


SUBSET = REPO / "data" / "pool-video"  # the few pool frames the repository ships


def pool_paths():
    """The pool frames: the full recording when ACTAG_DATA_DIR (../shared/data)
    has it, else the repository's subset."""
    for d in (POOL, SUBSET):
        paths = sorted(d.glob("f_*.pgm")) if d.is_dir() else []
        if paths:
            return paths
    return []


def family_file_dir():
    for d in (DATA / "families", REPO / "data" / "families"):
        if d.is_dir():
            return d
    return None


@pytest.fixture(scope="session")
def example_frame():
    return pyactag.read_pgm(EXAMPLE)


@pytest.fixture(scope="session")
def pool_frames():
    paths = pool_paths()
    if not paths:
        pytest.skip("pool frames not found in {} or {} (set ACTAG_DATA_DIR)".format(POOL, SUBSET))
    return [(p, pyactag.read_pgm(p)) for p in paths]


def _tool():
    env = os.environ.get("ACTAG_DETECT")
    if env:
        if not os.access(env, os.X_OK):
            pytest.fail("ACTAG_DETECT={} is not an executable".format(env))
        return env
    default = REPO / "build" / "examples" / "actag_detect"
    if not os.access(str(default), os.X_OK):
        pytest.skip("C tool not built ({}); build the repository or set ACTAG_DETECT"
                    .format(default))
    return str(default)


@pytest.fixture(scope="session")
def c_tool():
    return _tool()


def run_c_tool(tool, paths, extra=()):
    """actag_detect --json on the files; one dict per file, in order."""
    cmd = [tool, "--json", "--min-range", "0.1", "--max-range", "1.5", "--aperture-deg", "60",
           "--family", FAMILY, "--tag-size", str(TAG_SIZE)] + list(extra) + [str(p) for p in paths]
    out = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, universal_newlines=True).stdout
    lines = [json.loads(line) for line in out.splitlines() if line.strip()]
    assert len(lines) == len(paths)
    return lines


def c_corners_xy(det):
    """Corner (x = column, y = row) pairs from a detection of the C tool's JSON,
    whichever key it uses: 'corners_xy' ([x, y]), 'corners_rowcol' or the
    older 'corners_px' ([row, col]), or 'corners' ([{x_col, y_row, range_m,
    azimuth_rad}])."""
    if "corners" in det:
        return [(c["x_col"], c["y_row"]) for c in det["corners"]]
    if "corners_xy" in det:
        return [(c[0], c[1]) for c in det["corners_xy"]]
    if "corners_rowcol" in det:
        return [(c[1], c[0]) for c in det["corners_rowcol"]]
    if "corners_px" in det:
        return [(c[1], c[0]) for c in det["corners_px"]]
    raise KeyError("no corner key in the C tool's JSON: {}".format(sorted(det)))


def c_corners_polar(det):
    if "corners" in det:
        return [(c["range_m"], c["azimuth_rad"]) for c in det["corners"]]
    for key in ("corners_range_azimuth", "corners_polar"):
        if key in det:
            return [(c[0], c[1]) for c in det[key]]
    raise KeyError("no polar corner key in the C tool's JSON: {}".format(sorted(det)))


def assert_same_as_c(py_dets, c_line, where):
    """Python detections equal the C tool's JSON line (to its printed digits)."""
    c_dets = c_line["detections"]
    assert len(py_dets) == len(c_dets), "{}: {} vs {} detections".format(
        where, len(py_dets), len(c_dets))
    for d, c in zip(py_dets, c_dets):
        assert d.id == c["id"], where
        assert d.hamming == c["hamming"], where
        assert d.mirrored == c["mirrored"], where
        assert abs(d.decision_margin - c["decision_margin"]) <= 0.0051, where
        for (x, y), (cx, cy) in zip(d.corners_xy, c_corners_xy(c)):
            assert abs(x - cx) <= 0.00051 and abs(y - cy) <= 0.00051, where
        for (r, a), (cr, ca) in zip(d.corners_polar, c_corners_polar(c)):
            assert abs(r - cr) <= 0.0000051 and abs(a - ca) <= 0.0000051, where


def detections_key(dets):
    """Exact, comparable form of a detection list."""
    return [(d.id, d.hamming, d.mirrored, d.decision_margin, d.inlier_ratio, d.corners_xy,
             d.corners_polar) for d in dets]
