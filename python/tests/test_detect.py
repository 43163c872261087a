"""detect()/Detector on real frames: the same detections as the C tool,
parameters and their C defaults, results, stage images."""
import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import pyactag
from conftest import (EXAMPLE, FAMILY, GEOMETRY, REPO, TAG_SIZE, assert_same_as_c,
                      detections_key, freed_with_its_family, gc_clear, run_c_tool)

np = pytest.importorskip("numpy")


def test_extension_is_abi3():
    # One binary for every CPython >= 3.9: the limited-API module suffix.
    assert pyactag._core.__file__.endswith(".abi3.so"), pyactag._core.__file__


def test_example_frame(example_frame):
    assert example_frame.shape == (463, 620) and example_frame.dtype == np.uint8
    dets = pyactag.detect(example_frame, **GEOMETRY)
    assert len(dets) == 1
    d = dets[0]
    assert d.id == 0 and d.hamming <= 3 and d.decision_margin > 5
    # SPEC section 6: the reference finds tag 0 with corners (row, col)
    # (145,314) (113,339) (103,280) (133,244) and these (range, azimuth).
    ref_rc = [(145, 314), (113, 339), (103, 280), (133, 244)]
    ref_polar = [(1.0606, -0.0076), (1.1576, -0.0499), (1.1879, 0.0499), (1.0970, 0.1108)]
    # The corners are refined to the fitted tag (refine.h): within 4.5 px
    # of the reference's quad corners, as in test_detect (C).
    for (r, c), (rr, rc) in zip(d.corners_rowcol, ref_rc):
        assert abs(r - rr) < 4.5 and abs(c - rc) < 4.5
    for (r, a), (rr, ra) in zip(d.corners_polar, ref_polar):
        assert abs(r - rr) < 0.012 and abs(a - ra) < 0.008
    # x is the column, y the row.
    assert d.corners_rowcol[0] == (d.corners_xy[0][1], d.corners_xy[0][0])


def test_example_frame_same_as_c_tool(example_frame, c_tool):
    line = run_c_tool(c_tool, [EXAMPLE])[0]
    assert_same_as_c(pyactag.detect(example_frame, **GEOMETRY), line, "example")


def test_pool_frames_same_as_c_tool(pool_frames, c_tool):
    lines = run_c_tool(c_tool, [p for p, _ in pool_frames])
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, **GEOMETRY)
    found = 0
    for (path, frame), line in zip(pool_frames, lines):
        dets = det.detect(frame)
        assert_same_as_c(dets, line, path.name)
        found += len(dets)
        for d in dets:  # one physical tag, ID 0, in the whole recording
            assert d.id == 0, path.name
    # The C suite's floor is 34 of the 47 tagged frames among the 58.
    assert found >= len(pool_frames) // 2
    print("pool: {} frames, {} detections, all equal to actag_detect --json".format(
        len(pool_frames), found))


def test_pool_frames_other_settings_same_as_c_tool(pool_frames, c_tool):
    # A few non-default parameters through both front ends.
    paths = [p for p, _ in pool_frames[:12]]
    lines = run_c_tool(c_tool, paths, ["--decode", "binary", "--bit-corrections", "2", "--seed",
                                       "7", "--median-radius", "3", "--search", "0"])
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, decode_mode="binary",
                           max_bit_corrections=2, seed=7, median_radius=3, search_candidates=0,
                           **GEOMETRY)
    for (path, frame), line in zip(pool_frames[:12], lines):
        assert_same_as_c(det.detect(frame), line, path.name)
    # The least decision margin (actag_detect --min-margin): 12, or just
    # above the least default margin when all are above 12 (the repository's
    # six pool frames), so that it removes a reading either way.
    base = [pyactag.detect(frame, **GEOMETRY) for _, frame in pool_frames[:12]]
    margins = sorted(d.decision_margin for dets in base for d in dets)
    assert margins, "no detection in the first pool frames"
    least = 12.0 if margins[0] < 12.0 else math.floor(margins[0] * 100.0 + 1.0) / 100.0
    lines = run_c_tool(c_tool, paths, ["--min-margin", "{:.2f}".format(least)])
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, min_margin=least, **GEOMETRY)
    changed = 0
    for (path, frame), line, plain in zip(pool_frames[:12], lines, base):
        dets = det.detect(frame)
        assert_same_as_c(dets, line, path.name)
        assert all(d.decision_margin >= least for d in dets)
        # a reading below the margin is gone (another may take its place:
        # f_0561's 11.2 gives way to one of 14.3)
        changed += detections_key(dets) != detections_key(plain)
    assert changed > 0  # the margin changed something


def test_sixteen_bit_same_as_c_tool(example_frame, c_tool, tmp_path):
    f16 = (example_frame.astype(np.uint16) * 181 + 7).astype(np.uint16)
    path = tmp_path / "example16.pgm"
    pyactag.write_pgm(path, f16)
    assert np.array_equal(pyactag.read_pgm(path), f16)
    line = run_c_tool(c_tool, [path])[0]
    assert_same_as_c(pyactag.detect(f16, **GEOMETRY), line, "16-bit")


def test_defaults_are_the_c_defaults():
    p = pyactag.default_params()
    # actag_params_default() (include/actag/actag.h, src/detect.c)
    expected = dict(tag_size=0.130628571, max_bit_corrections=None, decode_mode="fit", seed=1,
                    median_radius=4, median_per_range=1, threshold_radius=8, threshold_offset=1,
                    size_tolerance=0.2,
                    min_area_fraction=0.175, max_area_fraction=1.0, quad_max_iterations=100,
                    quad_sample_fraction=0.1, quad_inlier_ratio=0.8, quad_inlier_distance=2.5,
                    quad_min_parallel_cos=0.9, quad_min_inlier_ratio=0.6, min_structure=0.0,
                    min_texture_contrast=5.0,
                    min_side_fraction=0.5, max_side_fraction=1.6, search_candidates=2,
                    search_min_score=15, search_max_corrections=3, search_min_margin=1.0,
                    search_range_scale=0.75, refine_corners=1, fit_level=0.5, fit_min_contrast=5,
                    fit_sample_offset=0.2, min_margin=2.0, fit_min_bit_margin=2, fit_min_bit_odds=100,
                    fit_many_corrections=3, fit_many_corrections_margin=1.5)
    for k, v in expected.items():
        if isinstance(v, float):  # C floats
            assert np.float32(p[k]) == np.float32(v), k
        else:
            assert p[k] == v, k
    assert p["fit_flags"] == (pyactag._core.FIT_LOCAL | pyactag._core.FIT_SPLIT |
                              pyactag._core.FIT_ERASE_CORNERS | pyactag._core.FIT_VERIFY |
                              pyactag._core.FIT_LEVEL_NOISE)
    assert pyactag._core.FIT_SEPARATE_NOISE & p["fit_flags"] == 0
    assert pyactag.Detector(**GEOMETRY).params == p
    # actag_params: the user settings, then actag_tuning.
    user = {"tag_size", "max_bit_corrections", "seed", "min_margin", "handedness"}
    assert set(pyactag.tuning_names()) == set(p) - user
    assert all(u in pyactag.tuning_names.__doc__ for u in user)  # its docstring lists them


def test_keyword_parameters_and_tuning_dict(example_frame):
    d = pyactag.Detector(median_radius=3, tuning={"quad_inlier_distance": 2.0}, seed=9,
                         max_bit_corrections=1)
    p = d.params
    assert (p["median_radius"], p["quad_inlier_distance"], p["seed"],
            p["max_bit_corrections"]) == (3, 2.0, 9, 1)
    with pytest.raises(TypeError, match="given twice"):
        pyactag.Detector(median_radius=3, tuning={"median_radius": 2})
    with pytest.raises(TypeError, match="not a tuning field"):
        pyactag.Detector(tuning={"seed": 2})
    # Parameters change the result as in C: no corrections allowed -> hamming 0 only.
    strict = pyactag.detect(example_frame, max_bit_corrections=0, search_candidates=0, **GEOMETRY)
    assert all(x.hamming == 0 for x in strict)


def test_geometry_in_detector_and_per_call(example_frame):
    det = pyactag.Detector(**GEOMETRY)
    a = det.detect(example_frame)
    b = pyactag.Detector().detect(example_frame, **GEOMETRY)
    c = det.detect(example_frame, aperture_deg=None, aperture=np.radians(60.0))
    assert detections_key(a) == detections_key(b) == detections_key(c)
    # An explicit bearing table equal to the uniform aperture.
    cols = example_frame.shape[1]
    half = np.radians(30.0)
    bearings = [half - i * 2 * half / (cols - 1) for i in range(cols)]
    e = pyactag.detect(example_frame, min_range=0.1, max_range=1.5, bearings=bearings)
    assert [x.id for x in e] == [x.id for x in a]
    # a Detector keeps a table given as an iterator for every frame (it was spent by the first)
    it = pyactag.Detector(min_range=0.1, max_range=1.5, bearings=iter(bearings))
    assert detections_key(it.detect(example_frame)) == detections_key(e)
    assert detections_key(it.detect(example_frame)) == detections_key(e)
    # geometry values a C float cannot hold are named (not "inf" or "0" from the library)
    with pytest.raises(OverflowError, match="max_range is outside the range of a C float"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1e39, aperture_deg=60)
    with pytest.raises(OverflowError, match="aperture is outside the range of a C float"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, aperture=1e-50)
    with pytest.raises(OverflowError, match=r"bearings\[3\] is outside"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5,
                       bearings=bearings[:3] + [1e-50] + bearings[4:])
    for x, y in zip(e, a):
        for (r1, a1), (r2, a2) in zip(x.corners_polar, y.corners_polar):
            assert abs(r1 - r2) < 1e-3 and abs(a1 - a2) < 1e-3


def test_orientation_flags(example_frame):
    # The same sonar stored nearest row first and most negative beam first.
    flipped = np.ascontiguousarray(example_frame[::-1, ::-1])
    dets = pyactag.detect(flipped, range_ascending=True, azimuth_ascending=True, **GEOMETRY)
    ref = pyactag.detect(example_frame, **GEOMETRY)
    assert [d.id for d in dets] == [d.id for d in ref]
    for x, y in zip(dets, ref):
        assert x.mirrored == y.mirrored
        for (r1, a1), (r2, a2) in zip(x.corners_polar, y.corners_polar):
            assert abs(r1 - r2) < 0.02 and abs(a1 - a2) < 0.02


def test_run_stats_and_stages(example_frame):
    res = pyactag.Detector(**GEOMETRY).run(example_frame, stages=True)
    assert len(res.detections) == 1
    assert res.stats["contours"] > 0 and res.stats["decoded"] >= 1 and res.stats["dropped"] == 0
    for k in ("filtered", "binary"):
        img = res.stages[k]
        assert img.shape == example_frame.shape and img.dtype == np.uint8
    assert set(np.unique(res.stages["binary"])) <= {0, 255}
    assert pyactag.Detector(**GEOMETRY).run(example_frame).stages is None
    none = pyactag.Detector(max_detections=0, **GEOMETRY).run(example_frame)
    assert none.detections == [] and none.stats["dropped"] == 1


def test_detection_object(example_frame):
    d = pyactag.detect(example_frame, **GEOMETRY)[0]
    dd = d.to_dict()
    assert json.loads(json.dumps(dd)) == dd
    assert dd["corners"][0] == {"x_col": d.corners_xy[0][0], "y_row": d.corners_xy[0][1],
                                "range_m": d.corners_polar[0][0],
                                "azimuth_rad": d.corners_polar[0][1]}
    assert d.corners[2].y_row == d.corners_rowcol[2][0] and d.corners[2].x_col == d.corners_xy[2][0]
    assert d.ranges_m == tuple(r for r, _ in d.corners_polar)
    assert d.azimuths_rad == tuple(a for _, a in d.corners_polar)
    cx, cy = d.center_xy
    assert 200 < cx < 400 and 80 < cy < 160
    assert "id=0" in repr(d)
    assert d == pyactag.detect(example_frame, **GEOMETRY)[0]


def test_workspace_kept_by_detector(example_frame):
    det = pyactag.Detector(**GEOMETRY)
    assert det._core.workspace_bytes == 0
    det.detect(example_frame)
    assert det._core.workspace_bytes == pyactag.workspace_size(*example_frame.shape)
    det.detect(example_frame[:200, :300])  # a smaller frame reuses it
    assert det._core.workspace_bytes == pyactag.workspace_size(*example_frame.shape)


def test_workspace_size_of_bad_sizes_is_zero():
    # "0 for bad sizes", as documented: sizes beyond a C int were an
    # OverflowError (workspace_size(2**31, 5); review).
    big = pyactag.workspace_size(530, 512)
    assert big == 398752 and pyactag.workspace_size(np.int64(530), np.uint16(512)) == big
    top = pyactag._core.MAX_DIM
    assert pyactag.workspace_size(top, 1) > 0
    for rows, cols in ((0, 5), (-1, 5), (top + 1, 5), (5, top + 1), (2 ** 31, 5), (5, 2 ** 31),
                       (-2 ** 31 - 1, 5), (2 ** 63, 2 ** 63), (-2 ** 100, 5),
                       (np.int64(2 ** 40), 5)):
        assert pyactag.workspace_size(rows, cols) == 0, (rows, cols)
        assert pyactag._core.workspace_size(rows, cols) == 0, (rows, cols)
    for bad in (1.5, "5", None):
        with pytest.raises(TypeError):
            pyactag.workspace_size(bad, 5)


def test_detector_family_cycle_is_collected(example_frame):
    # A Detector holds its Family; without GC support a cycle through it
    # (the family holding its detector) was never freed (review).
    assert freed_with_its_family(pyactag._core.Detector)
    assert freed_with_its_family(pyactag.Detector)
    # A Detector the collector cleared refuses to run rather than crash.
    det = pyactag._core.Detector(pyactag.Family(FAMILY))
    det.detect(example_frame, 0.1, 1.5, 1.0)  # a workspace to free later
    assert gc_clear(det) == 0
    with pytest.raises(RuntimeError, match="cleared"):
        det.detect(example_frame, 0.1, 1.5, 1.0)
    with pytest.raises(RuntimeError, match="cleared"):
        det.family
    assert det.params["tag_size"] > 0 and det.workspace_bytes > 0
    del det


def test_without_numpy(tmp_path):
    """numpy is optional: the same detections from a memoryview frame."""
    code = (
        "import json, sys, pyactag\n"
        "assert 'numpy' not in sys.modules and not pyactag.have_numpy()\n"
        "f = pyactag.read_pgm(sys.argv[1])\n"
        "assert isinstance(f, memoryview) and f.shape == (463, 620)\n"
        "d = pyactag.detect(f, min_range=0.1, max_range=1.5, aperture_deg=60)\n"
        "img = pyactag.Family('AcTag24h10').render(0, 4)\n"
        "assert isinstance(img, memoryview) and img.shape == (28, 28)\n"
        "print(json.dumps([x.to_dict() for x in d]))\n")
    env = dict(os.environ, PYACTAG_NO_NUMPY="1")
    # Block numpy outright so that an accidental import fails.
    blocker = tmp_path / "numpy.py"
    blocker.write_text("raise ImportError('numpy blocked by the test')\n")
    env["PYTHONPATH"] = str(tmp_path) + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, "-c", code, str(EXAMPLE)], env=env, check=True,
                         stdout=subprocess.PIPE, universal_newlines=True).stdout
    frame = pyactag.read_pgm(EXAMPLE)
    expected = [x.to_dict() for x in pyactag.detect(frame, **GEOMETRY)]
    assert json.loads(out) == json.loads(json.dumps(expected))


class MyDetector(pyactag.Detector):
    """A subclass (pickling must keep the class)."""


def test_pickle_detector_and_detections(example_frame):
    import pickle
    det = pyactag.Detector(median_radius=3, seed=9, max_detections=5, **GEOMETRY)
    copy = pickle.loads(pickle.dumps(det))
    assert copy is not det and copy.params == det.params and copy.geometry == det.geometry
    assert copy.max_detections == 5 and copy.family.name == det.family.name
    a = det.detect(example_frame)
    assert a, "the example frame shows a tag"
    assert detections_key(copy.detect(example_frame)) == detections_key(a)
    for proto in range(pickle.HIGHEST_PROTOCOL + 1):
        back = pickle.loads(pickle.dumps(a, protocol=proto))
        assert [d.to_dict() for d in back] == [d.to_dict() for d in a], proto
    # a bare core family, and a subclass, come back as they were
    raw = pyactag._core.Family("AcTag24h10")
    assert pickle.loads(pickle.dumps(pyactag.Detector(raw, **GEOMETRY))).family.name == "AcTag24h10"
    assert type(pickle.loads(pickle.dumps(MyDetector(**GEOMETRY)))) is MyDetector
    # a Detector with a caller's family keeps its codes
    fam = pyactag.Family.from_codes("MyTags", pyactag.Family("AcTag24h10").codes, bits=24,
                                    hamming=10)
    orig = pyactag.Detector(fam, **GEOMETRY)
    det2 = pickle.loads(pickle.dumps(orig))
    assert not det2.family.builtin and det2.family.codes == fam.codes
    assert detections_key(det2.detect(example_frame)) == detections_key(orig.detect(example_frame))


#: Every field of the C actag_stats (include/actag/actag.h), in its order.
STATS_KEYS = ("contours", "size_ok", "overflowed", "quads", "decoded", "duplicates", "dropped",
              "searched", "decodes", "iterations", "contour_cap", "ransac_exhausted",
              "contour_budget", "frame_budget", "decode_cap", "search_cap", "guess_cap")

#: Work limits small enough for the example frame to reach, and the counter
#: that says so.
LIMITS = ((dict(max_contours=5), "contour_cap"), (dict(max_decodes=1), "decode_cap"),
          (dict(max_frame_iterations=1), "frame_budget"))


def test_stats_have_every_counter(example_frame):
    header = (REPO / "include" / "actag" / "actag.h").read_text()
    struct = re.search(r"typedef struct actag_stats \{(.*?)\} actag_stats;", header, re.S).group(1)
    assert tuple(re.findall(r"\bint (\w+);", struct)) == STATS_KEYS
    stats = pyactag.Detector(**GEOMETRY).run(example_frame).stats
    assert sorted(stats) == sorted(STATS_KEYS)
    assert all(isinstance(v, int) and v >= 0 for v in stats.values())
    # documented where the stats are described
    readme = (REPO / "python" / "README.md").read_text()
    for k in STATS_KEYS:
        assert "| `{}` |".format(k) in readme, k
        assert k in _result_doc(), k


def _result_doc():
    """The comment block above Result in detection.py (its documentation)."""
    text = Path(pyactag.detection.__file__).read_text()
    return text[text.index("#: Result of"):text.index("Result = namedtuple")]


@pytest.mark.parametrize("limits, counter", LIMITS, ids=[c for _, c in LIMITS])
def test_limit_counters(example_frame, limits, counter):
    assert pyactag.Detector(**GEOMETRY).run(example_frame).stats[counter] == 0
    stats = pyactag.Detector(**limits, **GEOMETRY).run(example_frame).stats
    assert stats[counter] > 0, stats
    if counter == "contour_cap":
        assert stats["contours"] == 5


def _same_as_c_library(frame, c_library, where, **limits):
    """Counters, IDs, inlier ratios and margins equal libactag's own (the
    tool's JSON has neither counters nor inlier ratios). Returns the stats."""
    res = pyactag.Detector(**limits, **GEOMETRY).run(frame)
    c = c_library(frame, **limits)
    assert res.stats == c["stats"], where
    assert len(res.detections) == c["n"], where
    for d, cd in zip(res.detections, c["detections"]):
        assert d.id == cd["id"], where
        # float32 values, printed with 9 digits: exact
        assert np.float32(d.inlier_ratio) == np.float32(cd["inlier_ratio"]), where
        assert np.float32(d.decision_margin) == np.float32(cd["decision_margin"]), where
    return res


def test_stats_and_inlier_ratio_same_as_c_library(example_frame, c_library):
    res = _same_as_c_library(example_frame, c_library, "example")
    # the frame tells the fields apart: a detection, and counters that differ
    # (decoded counts the structure search's readings too)
    assert res.detections and 0 < res.detections[0].inlier_ratio <= 1
    s = res.stats
    assert s["quads"] != s["decoded"] and s["searched"] > 0 and s["iterations"] > 0, s
    for limits, counter in LIMITS:
        assert _same_as_c_library(example_frame, c_library, counter, **limits).stats[counter] > 0


def test_pool_stats_same_as_c_library(pool_frames, c_library):
    for path, frame in pool_frames[::5]:
        _same_as_c_library(frame, c_library, path.name)
    path, frame = pool_frames[0]
    _same_as_c_library(frame, c_library, path.name, max_contours=40, max_decodes=2,
                       max_frame_iterations=300)
