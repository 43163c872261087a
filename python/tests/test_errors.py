"""Errors are Python exceptions carrying the library's message."""
import re
from unittest import mock

import pytest

import pyactag
from conftest import GEOMETRY, REPO, detections_key

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
        pyactag.Detector(median_per_range=2)
    library_error(ei, "ACTAG_ERR_PARAM")
    assert ei.value.field == "median_per_range"
    assert "must be 0 or 1 (got 2)" in str(ei.value)
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


def test_geometry_types_refused(example_frame):
    # bool("False") is True: a str flag would flip the orientation silently.
    with pytest.raises(TypeError, match="range_ascending must be a bool, got 'False'"):
        pyactag.detect(example_frame, range_ascending="False", **GEOMETRY)
    with pytest.raises(TypeError, match="azimuth_ascending must be a bool, got 1"):
        pyactag.Detector(azimuth_ascending=1)
    with pytest.raises(TypeError, match="range_ascending must be a bool, got None"):
        pyactag.Detector(**GEOMETRY).detect(example_frame, range_ascending=None)
    with pytest.raises(TypeError, match="min_range must be a real number, got True"):
        pyactag.Detector(min_range=True, max_range=1.5, aperture_deg=60)
    with pytest.raises(TypeError, match="aperture_deg must be a real number, got '60'"):
        pyactag.Detector(min_range=0.1, max_range=1.5, aperture_deg="60")
    with pytest.raises(TypeError, match="aperture must be a real number, got '1'"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, aperture="1")
    with pytest.raises(TypeError, match="max_range must be a real number, got '1.5'"):
        pyactag.Detector(**GEOMETRY).detect(example_frame, max_range="1.5")
    bearings = list(np.linspace(0.5, -0.5, 620))
    for bad, shown in (("a", "'a'"), (True, "True"), (None, "None")):
        with pytest.raises(TypeError, match=r"bearings\[7\] must be a real number, got " + shown):
            pyactag.detect(example_frame, min_range=0.1, max_range=1.5,
                           bearings=bearings[:7] + [bad] + bearings[8:])
    with pytest.raises(TypeError, match="bearings must be a sequence"):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, bearings="0.5")
    # numpy numbers and bools are numbers and bools.
    flipped = np.ascontiguousarray(example_frame[::-1])
    assert (detections_key(pyactag.detect(flipped, range_ascending=np.bool_(True),
                                          min_range=np.float32(0.1), max_range=np.int64(1) + 0.5,
                                          aperture_deg=np.float64(60))) ==
            detections_key(pyactag.detect(flipped, range_ascending=True, **GEOMETRY)))


def test_per_frame_field_of_view_replaces_the_stored_one(example_frame):
    cols = example_frame.shape[1]
    bearings = np.linspace(np.radians(30), -np.radians(30), cols)
    ref = detections_key(pyactag.detect(example_frame, **GEOMETRY))
    assert ref
    det = pyactag.Detector(**GEOMETRY)  # aperture_deg stored
    assert detections_key(det.detect(example_frame, aperture=np.radians(60))) == ref
    wide = detections_key(pyactag.detect(example_frame, min_range=0.1, max_range=1.5,
                                         bearings=bearings * 1.2))
    assert detections_key(det.detect(example_frame, bearings=bearings * 1.2)) == wide
    byrad = pyactag.Detector(min_range=0.1, max_range=1.5, aperture=1.0)
    assert detections_key(byrad.detect(example_frame, aperture_deg=60)) == ref
    bybearings = pyactag.Detector(min_range=0.1, max_range=1.5, bearings=bearings * 1.2)
    assert detections_key(bybearings.detect(example_frame, aperture_deg=60)) == ref
    assert detections_key(bybearings.detect(example_frame)) == wide  # the stored form is kept
    # Two forms in one call (or one constructor) stay an error.
    with pytest.raises(ValueError, match="not both"):
        det.detect(example_frame, aperture=1.0, aperture_deg=60)
    with pytest.raises(ValueError, match="not both"):
        det.detect(example_frame, aperture=1.0, bearings=bearings)
    with pytest.raises(ValueError, match="not both"):
        pyactag.Detector(min_range=0.1, max_range=1.5, aperture=1.0, aperture_deg=60)


@pytest.mark.parametrize("name", ["max_contours", "max_contour_points", "max_contour_iterations",
                                  "max_frame_iterations", "max_decodes"])
def test_limit_errors_name_the_keyword(name):
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Detector(**{name: 0})
    library_error(ei, "ACTAG_ERR_PARAM")
    assert ei.value.field == name
    assert "invalid parameters: {} must be an integer >= 1 (got 0)".format(name) in str(ei.value)
    assert "limits" not in str(ei.value)
    assert name in pyactag.tuning_names()
    readme = (REPO / "python" / "README.md").read_text()
    assert "`{}`".format(name) in readme


@pytest.mark.parametrize("value, error", [(None, TypeError), ("x", TypeError), (2.7, TypeError),
                                          (float("nan"), TypeError), (True, TypeError),
                                          (2 ** 40, ValueError), (-1, ValueError),
                                          (4097, ValueError)])
def test_max_detections_checked(example_frame, value, error):
    with pytest.raises(error, match="max_detections"):
        pyactag.detect(example_frame, max_detections=value, **GEOMETRY)
    with pytest.raises(error, match="max_detections"):
        pyactag.Detector(max_detections=value)
    if value is not None:  # run(max_detections=None) is the detector's own
        with pytest.raises(error, match="max_detections"):
            pyactag.Detector(**GEOMETRY).run(example_frame, max_detections=value)


def test_max_detections_accepts_integers(example_frame):
    assert len(pyactag.detect(example_frame, max_detections=np.int32(1), **GEOMETRY)) == 1
    assert pyactag.Detector(max_detections=4096).max_detections == 4096
    assert pyactag.Detector(**GEOMETRY).run(example_frame, max_detections=0).detections == []


def test_nul_in_names_refused():
    with pytest.raises(ValueError, match=r"family name 'AcTag24h10\\x00junk' contains a NUL"):
        pyactag.Family("AcTag24h10\x00junk")
    with pytest.raises(ValueError, match="NUL"):
        pyactag.Family.from_codes("Mine\x00", [1], bits=24, hamming=4)
    with pytest.raises(ValueError, match="NUL"):
        pyactag.Detector(**{"median_radius\x00junk": 3})


class FakeFamily(int):
    """Claims to be a Family through __class__, which isinstance() believes;
    it holds no actag_family for the C code to read."""
    __class__ = property(lambda self: pyactag._core.Family)


@pytest.mark.parametrize("make", [lambda: FakeFamily(5),
                                  lambda: mock.Mock(spec=pyactag.Family)],
                         ids=["class-attribute", "mock-spec"])
def test_object_posing_as_family_refused(example_frame, make):
    fake = make()
    assert isinstance(fake, pyactag._core.Family)  # what the old check trusted
    with pytest.raises(TypeError, match=r"family must be a pyactag\.Family, not .*type"):
        det = pyactag._core.Detector(fake, None)
        det.detect(example_frame, 0.1, 1.5, 1.0)  # read memory outside the object
    with pytest.raises(TypeError, match="family must be a name or a pyactag.Family, not"):
        pyactag.Detector(fake, **GEOMETRY)
    # real families, subclasses included, still pass
    assert pyactag._core.Detector(pyactag.Family("AcTag24h10"), None).family.name == "AcTag24h10"
    assert pyactag.Detector(pyactag._core.Family("AcTag24h10")).family.name == "AcTag24h10"


@pytest.mark.parametrize("value", [np.True_, np.False_, True])
def test_bool_is_no_number(example_frame, value):
    # README: a bool for a number is a TypeError; numpy's bool too (it would
    # have been read as 1.0 or 0.0).
    shown = re.escape(repr(value))
    for name in ("tag_size", "min_margin", "quad_inlier_ratio", "fit_level"):
        with pytest.raises(TypeError, match=r"parameter '{}' must be a number, not bool \(got {}\)"
                           .format(name, shown)):
            pyactag.Detector(**{name: value})
    for name in ("median_radius", "seed", "max_bit_corrections"):
        with pytest.raises(TypeError, match=r"parameter '{}' must be an integer, not bool \(got {}\)"
                           .format(name, shown)):
            pyactag.Detector(**{name: value})
    bearings = list(np.linspace(0.5, -0.5, example_frame.shape[1]))
    bearings[7] = value
    with pytest.raises(TypeError, match=r"bearings\[7\] must be a real number, got " + shown):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, bearings=bearings)


def test_out_of_range_parameters_name_the_value():
    with pytest.raises(OverflowError, match=r"parameter 'median_radius' must be an integer from "
                                            r"-2147483648 to 2147483647, got 1099511627776$"):
        pyactag.Detector(median_radius=2 ** 40)
    with pytest.raises(OverflowError, match=r"parameter 'seed' must be an integer from 0 to "
                                            r"4294967295, got -1$"):
        pyactag.Detector(seed=np.int64(-1))
    with pytest.raises(OverflowError, match=r"parameter 'max_bit_corrections' must be an integer "
                                            r"from -1 to 2147483647, got -2$"):
        pyactag.Detector(max_bit_corrections=-2)
    # A nonzero value a C float cannot hold is refused by its own value, not
    # passed on as 0 or inf for the library to report as "got 0" / "got inf".
    for value in (1e-50, -1e-50, np.float64(1e-60), 1e300, -1e300, np.float64(4e38), 10 ** 39):
        with pytest.raises(OverflowError, match=r"parameter 'tag_size' is outside the range of a "
                                                r"C float \(.*\), got {}$".format(
                                                    re.escape(repr(value)))):
            pyactag.Detector(tag_size=value)
    with pytest.raises(OverflowError, match=r"parameter 'min_margin' is outside the range of a "
                                            r"C float, got 10{400}$"):
        pyactag.Detector(min_margin=10 ** 400)  # beyond a double as well
    # What a float holds is the library's to judge: a subnormal, NaN and the
    # infinities reach its check, which names the field and the value.
    assert pyactag.Detector(min_margin=1e-40).params["min_margin"] == pytest.approx(1e-40, 1e-4)
    for value, shown in ((float("inf"), "inf"), (-float("inf"), "-inf"), (float("nan"), "nan")):
        for name in ("tag_size", "min_margin", "quad_inlier_distance"):
            with pytest.raises(pyactag.ActagError) as ei:
                pyactag.Detector(**{name: value})
            library_error(ei, "ACTAG_ERR_PARAM")
            assert ei.value.field == name
            assert "invalid parameters: {} must be".format(name) in str(ei.value)
            assert "(got {})".format(shown) in str(ei.value)


def test_azimuth_ascending_refused_with_bearings(example_frame):
    # The bearing table gives each column's azimuth: the flag would be
    # ignored, so it is refused (as actag_detect --bearings refuses it).
    cols = example_frame.shape[1]
    bearings = list(np.linspace(np.radians(30), -np.radians(30), cols))
    msg = "azimuth_ascending=True does not apply with bearings"
    with pytest.raises(ValueError, match=msg):
        pyactag.detect(example_frame, min_range=0.1, max_range=1.5, bearings=bearings,
                       azimuth_ascending=True)
    with pytest.raises(ValueError, match=msg):
        pyactag.Detector(min_range=0.1, max_range=1.5, bearings=bearings,
                         azimuth_ascending=np.True_)
    with pytest.raises(ValueError, match=msg):  # the flag stored, the table per call
        pyactag.Detector(azimuth_ascending=True, **GEOMETRY).detect(example_frame,
                                                                   bearings=bearings)
    with pytest.raises(ValueError, match=msg):  # and the other way round
        pyactag.Detector(min_range=0.1, max_range=1.5, bearings=bearings).detect(
            example_frame, azimuth_ascending=True)
    with pytest.raises(ValueError, match=msg):  # the extension refuses it too
        pyactag._core.Detector(pyactag.Family("AcTag24h10")).detect(
            example_frame, 0.1, 1.5, None, bearings, False, True)
    # False with a table, True with an aperture: as before.
    plain = detections_key(pyactag.detect(example_frame, min_range=0.1, max_range=1.5,
                                          bearings=bearings))
    assert plain and detections_key(pyactag.detect(
        example_frame, min_range=0.1, max_range=1.5, bearings=bearings,
        azimuth_ascending=False)) == plain
    det = pyactag.Detector(azimuth_ascending=True, **GEOMETRY)
    assert det.detect(np.ascontiguousarray(example_frame[:, ::-1]))
    assert detections_key(det.detect(example_frame, bearings=bearings,
                                     azimuth_ascending=False)) == plain


def test_endless_bearings_refused():
    # Reading stops at the first value past the frame's columns: an endless
    # iterator hung the call before, uninterruptibly (review). The guard
    # fails if more than cols + 1 values are drawn.
    import itertools
    frame = np.zeros((4, 4), np.uint8)
    drawn = []

    def guarded():
        for i in itertools.count():
            assert i <= 4, "bearings read past cols + 1 values"
            drawn.append(i)
            yield 0.5 - i / 8.0

    with pytest.raises(ValueError, match="bearings has more than 4 values, the frame has 4 "
                                         "columns"):
        pyactag.detect(frame, min_range=0.1, max_range=1.5, bearings=guarded())
    assert drawn == [0, 1, 2, 3, 4]
    with pytest.raises(ValueError, match="more than 4 values"):
        pyactag.detect(frame, min_range=0.1, max_range=1.5, bearings=itertools.count())
    core = pyactag._core.Detector(pyactag.Family("AcTag24h10"))
    with pytest.raises(ValueError, match="more than 4 values"):
        core.detect(frame, 0.1, 1.5, None, itertools.repeat(0.1))
    tr = pyactag._core.Tracker(pyactag.Family("AcTag24h10"))
    with pytest.raises(ValueError, match="more than 4 values"):
        tr.update(frame, 0.1, 1.5, None, itertools.repeat(0.1))
    # the constructors keep a default geometry: an endless iterator there
    # is refused after MAX_DIM + 1 values (it hung them)
    for make in (pyactag.Detector, pyactag.Tracker):
        with pytest.raises(ValueError, match="more than {} values".format(pyactag._core.MAX_DIM)):
            make("AcTag24h10", min_range=0.1, max_range=1.5, bearings=itertools.count())
    assert tr.frame == 0
    # a sequence one too long still says how long it is; the right length works
    with pytest.raises(ValueError, match="bearings has 5 values, the frame has 4 columns"):
        core.detect(frame, 0.1, 1.5, None, [0.4, 0.2, 0.0, -0.2, -0.4])
    assert core.detect(frame, 0.1, 1.5, None, iter([0.3, 0.1, -0.1, -0.3]))[0] == []
