"""Errors are Python exceptions carrying the library's message."""
import pytest

import pyactag
from conftest import GEOMETRY

np = pytest.importorskip("numpy")


def library_error(excinfo, name):
    e = excinfo.value
    assert isinstance(e, pyactag.ActagError) and isinstance(e, ValueError)
    assert e.name == name
    assert pyactag.strerror(e.code) in str(e)  # the library's own message
    assert name in str(e)


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int16, np.int32, np.int8, bool])
def test_wrong_pixel_type(example_frame, dtype):
    with pytest.raises(TypeError, match="uint8 or uint16"):
        pyactag.detect(example_frame.astype(dtype), **GEOMETRY)


def test_wrong_dimensions(example_frame):
    with pytest.raises(ValueError, match="2-D"):
        pyactag.detect(example_frame.ravel(), **GEOMETRY)
    with pytest.raises(ValueError, match="2-D"):
        pyactag.detect(np.zeros((4, 5, 3), np.uint8), **GEOMETRY)
    with pytest.raises(ValueError, match="rows and columns"):
        pyactag.detect(np.zeros((0, 5), np.uint8), **GEOMETRY)
    with pytest.raises(ValueError, match="2-D"):
        pyactag.detect(b"\0" * 100, **GEOMETRY)
    with pytest.raises(TypeError, match="buffer protocol"):
        pyactag.detect(object(), **GEOMETRY)
    with pytest.raises(TypeError):
        pyactag.detect("not a frame", **GEOMETRY)


def test_geometry_errors(example_frame):
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.detect(example_frame, min_range=1.5, max_range=0.1, aperture_deg=60)
    library_error(ei, "ACTAG_ERR_GEOMETRY")
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, aperture_deg=400)
    library_error(ei, "ACTAG_ERR_GEOMETRY")
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, bearings=[0.0] * 620)
    library_error(ei, "ACTAG_ERR_GEOMETRY")  # not strictly monotonic
    assert ei.value.field == "bearings[1]"
    with pytest.raises(ValueError, match="620 columns"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, bearings=[0.0, 1.0])
    with pytest.raises(ValueError, match="not both"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, aperture=1.0,
                       bearings=np.linspace(0.5, -0.5, 620))
    with pytest.raises(ValueError, match="aperture"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5)
    with pytest.raises(ValueError, match="required"):
        pyactag.detect(example_frame, max_range=1.5, aperture_deg=60)  # no silent min_range 0
    with pytest.raises(TypeError, match="geometry keyword"):
        pyactag.Detector(**GEOMETRY).detect(example_frame, median_radius=3)


def test_parameter_errors():
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(median_radius=-1)
    library_error(ei, "ACTAG_ERR_PARAM")
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(tag_size=0.0)
    library_error(ei, "ACTAG_ERR_PARAM")
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(max_bit_corrections=5)  # AcTag24h10 allows 4
    library_error(ei, "ACTAG_ERR_CORRECTIONS")
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(quad_inlier_ratio=float("nan"))
    library_error(ei, "ACTAG_ERR_PARAM")
    assert ei.value.field == "quad_inlier_ratio"  # the library's detail, in Python's names
    assert "must be a number > 0 and <= 1 (got nan)" in str(ei.value)
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(quad_inlier_distance=1e7)  # RANSAC would refuse it: an error now
    assert ei.value.field == "quad_inlier_distance"
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(fit_many_corrections_margin=-1.0)
    library_error(ei, "ACTAG_ERR_PARAM")
    assert ei.value.field == "fit_many_corrections_margin"
    assert "must be a number from 0 to 1e6 (got -1)" in str(ei.value)
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector("AcTag99h1")
    library_error(ei, "ACTAG_ERR_FAMILY")
    assert "unknown family 'AcTag99h1'" in str(ei.value) and "AcTag24h10" in str(ei.value)
    with pytest.raises(TypeError, match="unknown parameter 'median_radiu'"):
        pyactag.Detector(median_radiu=3)
    with pytest.raises(TypeError, match="must be an integer"):
        pyactag.Detector(median_radius=2.5)
    with pytest.raises(TypeError, match="must be an integer"):
        pyactag.Detector(median_radius=True)
    with pytest.raises(TypeError, match="must be a number"):
        pyactag.Detector(tag_size="big")
    with pytest.raises(OverflowError):
        pyactag.Detector(seed=-1)
    with pytest.raises(OverflowError):
        pyactag.Detector(median_radius=2 ** 40)
    with pytest.raises(ValueError, match="'fit' or 'binary'"):
        pyactag.Detector(decode_mode="fast")
    with pytest.raises(ValueError, match="max_detections"):
        pyactag.Detector(max_detections=-1).detect(np.zeros((20, 20), np.uint8), **GEOMETRY)
    with pytest.raises(TypeError, match="family"):
        pyactag.Detector(family=3)


def test_numpy_integers_accepted():
    d = pyactag.Detector(median_radius=np.int64(3), tag_size=np.float32(0.2))
    assert d.params["median_radius"] == 3 and abs(d.params["tag_size"] - 0.2) < 1e-7


def test_errors_leave_detector_usable(example_frame):
    det = pyactag.Detector(**GEOMETRY)
    with pytest.raises(pyactag.ActagError):
        det.detect(example_frame, max_range=0.01)
    with pytest.raises(TypeError):
        det.detect(example_frame.astype(np.float32))
    assert len(det.detect(example_frame)) == 1
