"""Shared fixtures: repository paths, frames, the C tool's JSON output.

Environment:
  ACTAG_DATA_DIR  the real data (default: <repo>/../shared/data); tests that
                  need the pool frames skip visibly when it is absent.
  ACTAG_DETECT    the C tool actag_detect (default: <repo>/build/examples/
                  actag_detect); when set it must exist, otherwise the
                  comparisons with it skip visibly when it is not built.
                  The library of the same build (libactag.a or .so in the
                  folder above the tool's) serves c_stats.c, compiled with
                  $CC (default: Python's compiler, else cc): what the
                  library returns that the tool's JSON does not print
                  (counters, inlier ratios).
"""
import json
import math
import os
import shlex
import shutil
import subprocess
import sysconfig
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


@pytest.fixture(scope="session")
def c_library(c_tool, tmp_path_factory):
    """run(frame, **limits) -> libactag's own answer for an 8-bit frame
    (tests/c_stats.c): {"n", "detections": [{"id", "inlier_ratio",
    "decision_margin"}], "stats": {every actag_stats field}}, at the
    geometry GEOMETRY and the C defaults but for the integer tuning fields
    given (max_contours, max_contour_iterations, max_frame_iterations,
    max_decodes, search_candidates)."""
    build = Path(c_tool).resolve().parents[1]
    libs = [p for p in (build / "libactag.a", build / "libactag.so") if p.exists()]
    if not libs:
        pytest.skip("no libactag.a or libactag.so in {} (the build of {})".format(build, c_tool))
    cc = shlex.split(os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc")
    if not cc or shutil.which(cc[0]) is None:
        cc = ["cc"]
        if shutil.which("cc") is None:
            pytest.skip("no C compiler (set CC) to build tests/c_stats.c")
    exe = tmp_path_factory.mktemp("c_stats") / "c_stats"
    lib = libs[0]
    cmd = cc + ["-std=c99", "-O1", "-Wall", "-Wextra", "-Werror", "-I", str(REPO / "include"),
                "-I", str(build / "include"), str(Path(__file__).with_name("c_stats.c")),
                str(lib), "-lm", "-o", str(exe)]
    if lib.suffix == ".so":
        cmd.append("-Wl,-rpath," + str(build))
    subprocess.run(cmd, check=True)
    aperture = math.radians(GEOMETRY["aperture_deg"])
    assert (GEOMETRY["min_range"], GEOMETRY["max_range"]) == (0.1, 1.5)  # as c_stats.c sets them

    def run(frame, **limits):
        raw = exe.parent / "frame.raw"
        assert frame.dtype.itemsize == 1 and frame.ndim == 2
        raw.write_bytes(frame.tobytes())
        args = [str(exe), str(raw), str(frame.shape[0]), str(frame.shape[1]), repr(aperture)]
        args += ["{}={}".format(k, v) for k, v in sorted(limits.items())]
        out = subprocess.run(args, check=True, stdout=subprocess.PIPE,
                             universal_newlines=True).stdout
        return json.loads(out)

    return run


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


def freed_with_its_family(make):
    """True when a cycle Family -> make(family) -> Family is freed by the
    cyclic collector (the C objects holding a Family must let it see them)."""
    import gc
    import weakref
    fam = pyactag.Family(FAMILY)
    fam.user_object = make(fam)
    ref = weakref.ref(fam)
    del fam
    gc.collect()
    return ref() is None


def gc_clear(obj):
    """Run obj's tp_clear, as the cyclic collector does on a cycle (ctypes)."""
    ctypes = pytest.importorskip("ctypes")
    get_slot = ctypes.pythonapi.PyType_GetSlot
    get_slot.restype, get_slot.argtypes = ctypes.c_void_p, [ctypes.py_object, ctypes.c_int]
    addr = get_slot(type(obj), 51)  # Py_tp_clear
    assert addr, "{} has no tp_clear".format(type(obj).__name__)
    return ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.py_object)(addr)(obj)
