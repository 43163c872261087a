"""pyactag.AcTag: the reference package's constructor and output layout."""
import inspect
import warnings

import pytest

import pyactag
from conftest import GEOMETRY, detections_key

np = pytest.importorskip("numpy")

# actag 1.0.1 (PyPI), actag.AcTag.__init__, in order.
REFERENCE_ARGUMENTS = [
    "min_range", "max_range", "horizontal_aperture", "tag_family", "tag_size",
    "median_filter_kernel_radius", "adaptive_threshold_kernel_radius",
    "adaptive_threshold_offset", "contours_tag_size_tolerance", "contours_tag_area_tolerance",
    "contours_min_tag_area_ratio", "contours_reject_black_shapes",
    "contours_reject_white_shapes", "contours_reject_by_tag_size", "contours_reject_by_area",
    "quads_random_seed", "quads_points_per_line_ratio", "quads_dist_for_inlier",
    "quads_desired_inlier_ratio", "quads_required_inlier_ratio", "quads_parallel_threshold",
    "quads_use_same_random_vals", "quads_starting_roll_val", "decoding_num_bit_corrections",
    "use_optimized_rust_code",
]
APERTURE = 1.0472  # the reference's example value (60 degrees)


def make(**kw):
    return pyactag.AcTag(0.1, 1.5, APERTURE, "AcTag24h10", 0.130628571, **kw)


def test_constructor_matches_the_reference():
    params = list(inspect.signature(pyactag.AcTag.__init__).parameters)
    assert params[0] == "self"
    assert params[1:1 + len(REFERENCE_ARGUMENTS)] == REFERENCE_ARGUMENTS
    # Positional use as in the reference's examples.
    tag = pyactag.AcTag(0.1, 1.5, APERTURE, "AcTag24h10", 0.130628571, 4, 8, 1)
    assert tag.detector.params["median_radius"] == 4


def test_run_detection_layout(example_frame):
    tag = make()
    out = tag.run_detection(example_frame)
    assert isinstance(out, list) and len(out) == 1
    tag_id, corners, polar = out[0]
    assert type(tag_id) is int and tag_id == 0
    assert isinstance(corners, np.ndarray) and corners.shape == (4, 2)
    assert corners.dtype.kind == "i"
    assert isinstance(polar, np.ndarray) and polar.shape == (4, 2) and polar.dtype == float
    det = pyactag.detect(example_frame, min_range=0.1, max_range=1.5, aperture=APERTURE)[0]
    # [row, column] pairs, rounded; [range, azimuth] pairs.
    assert corners.tolist() == [[round(y), round(x)] for x, y in det.corners_xy]
    assert polar.tolist() == [list(p) for p in det.corners_polar]
    assert tag.run_detection_rust(example_frame)[0][0] == 0
    assert tag.run_detection_python(example_frame)[0][0] == 0


def test_defaults_are_libactag_and_arguments_map():
    assert {k: v for k, v in make().detector.params.items()} == pyactag.default_params()
    p = make(median_filter_kernel_radius=3, adaptive_threshold_kernel_radius=6,
             adaptive_threshold_offset=2.0, quads_random_seed=5, quads_points_per_line_ratio=0.2,
             quads_dist_for_inlier=2.0, quads_desired_inlier_ratio=0.85,
             quads_required_inlier_ratio=0.8, quads_parallel_threshold=0.95,
             decoding_num_bit_corrections=4).detector.params
    got = (p["median_radius"], p["threshold_radius"], p["threshold_offset"], p["seed"],
           p["max_bit_corrections"])
    assert got == (3, 6, 2, 5, 4)
    for key, v in (("quad_sample_fraction", 0.2), ("quad_inlier_distance", 2.0),
                   ("quad_inlier_ratio", 0.85), ("quad_min_inlier_ratio", 0.8),
                   ("quad_min_parallel_cos", 0.95)):
        assert np.float32(p[key]) == np.float32(v), key
    # The reference's contour filter, expressed in libactag's fractions.
    q = make(contours_tag_size_tolerance=0.3, contours_tag_area_tolerance=0.1,
             contours_min_tag_area_ratio=0.2).detector.params
    assert abs(q["size_tolerance"] - 0.3) < 1e-6
    assert abs(q["min_area_fraction"] * (1 - 0.3) - 0.2 * (1 - 0.1)) < 1e-6
    assert abs(q["max_area_fraction"] * (1 + 0.3) - (1 + 0.1)) < 1e-6
    r = make(contours_reject_by_area=False).detector.params
    assert r["min_area_fraction"] == 0.0 and r["max_area_fraction"] >= 1e5
    assert make(libactag_params={"search_candidates": 0, "min_margin": 2.0}).detector.params["search_candidates"] == 0
    with pytest.raises(TypeError, match="libactag_params"):
        make(median_filter_kernel_radius=3, libactag_params={"median_radius": 2})


def test_reference_errors():
    with pytest.raises(ValueError, match="between 0 and 4 with tag family AcTag24h10"):
        make(decoding_num_bit_corrections=5)
    with pytest.raises(ValueError, match=">= 0"):
        make(decoding_num_bit_corrections=-1)
    with pytest.raises(ValueError, match="whole number"):
        make(adaptive_threshold_offset=1.5)
    with pytest.raises(ValueError, match="white shapes"):
        make(contours_reject_white_shapes=True)
    with pytest.raises(ValueError, match="size filter"):
        make(contours_reject_by_tag_size=False)
    with pytest.raises(ValueError, match="neither built in"):
        pyactag.AcTag(0.1, 1.5, APERTURE, "AcTag24h11", 0.13)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        make(quads_use_same_random_vals=True)
    assert any("no effect" in str(x.message) for x in w)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        make(quads_starting_roll_val=7)
    assert any("quads_starting_roll_val has no effect" in str(x.message) for x in w)
    # checked, not converted (int(2.7) was 2, "3" was 3, True was 1)
    for kw in (dict(median_filter_kernel_radius=2.7), dict(median_filter_kernel_radius="3"),
               dict(median_filter_kernel_radius=True), dict(quads_random_seed=5.9),
               dict(decoding_num_bit_corrections=2.9), dict(quads_desired_inlier_ratio="0.9"),
               dict(contours_reject_by_tag_size=0), dict(adaptive_threshold_offset="1")):
        with pytest.raises(TypeError):
            make(**kw)
    with pytest.raises(ValueError, match="size filter"):
        make(contours_reject_by_tag_size=np.False_)
    assert make(median_filter_kernel_radius=np.int64(3)).detector.params["median_radius"] == 3


def test_family_file_argument(tmp_path, example_frame):
    fam = pyactag.Family("AcTag24h10")
    path = tmp_path / "AcTag24h10.txt"
    path.write_text("\n".join(hex(c) for c in fam.codes) + "\n")
    tag = pyactag.AcTag(0.1, 1.5, APERTURE, str(path), 0.130628571)
    assert not tag.family.builtin
    assert [t[0] for t in tag.run_detection(example_frame)] == [0]
    tag = pyactag.AcTag(0.1, 1.5, APERTURE, path, 0.130628571)  # a pathlib.Path
    assert tag.family.codes == fam.codes and not tag.family.builtin
    with pytest.raises(TypeError, match="tag_family must be a family name or a file path"):
        pyactag.AcTag(0.1, 1.5, APERTURE, 24, 0.130628571)
    with pytest.raises(TypeError, match="horizontal_aperture must be a real number, got '1'"):
        pyactag.AcTag(0.1, 1.5, "1", "AcTag24h10", 0.130628571)


def test_image_types(example_frame):
    tag = make()
    ref = tag.run_detection(example_frame)
    for arr in (example_frame.astype(np.int64), example_frame.astype(np.int32),
                example_frame.astype(np.uint16)):
        out = tag.run_detection(arr)
        assert [t[0] for t in out] == [t[0] for t in ref]
    same = tag.run_detection(example_frame.astype(np.int64))
    assert np.array_equal(same[0][1], ref[0][1])
    with pytest.raises(TypeError, match="integer grey levels"):
        tag.run_detection(example_frame.astype(np.float32) / 255)
    with pytest.raises(ValueError, match="2-D"):
        tag.run_detection(np.dstack([example_frame] * 3))


def test_imports_beside_the_reference(example_frame):
    """When the reference package is installed, both import in one process."""
    ref = pytest.importorskip("actag", reason="reference package (pip install actag) not installed")
    assert ref.AcTag is not pyactag.AcTag
    theirs = ref.AcTag(min_range=0.1, max_range=1.5, horizontal_aperture=APERTURE,
                       tag_family="AcTag24h10", tag_size=0.130628571, quads_random_seed=1)
    ours = make()
    a, b = theirs.run_detection(example_frame), ours.run_detection(example_frame)
    for x in a + b:  # same layout
        assert isinstance(x[0], int) and x[1].shape == (4, 2) and x[2].shape == (4, 2)
