"""sonar_pose / Detector.pose: the same poses as actag_detect --json --pose
(every pool frame, the example, a known plane, other settings), synthetic
corners of a known pose, the flags, and every bad argument named."""
import math
import pickle

import pytest

import pyactag
from conftest import EXAMPLE, FAMILY, GEOMETRY, TAG_SIZE, run_c_tool


def assert_pose_as_c(p, c, where):
    """A Pose against the tool's "pose" object, to the digits it prints
    (%.5f for t, range, angles and the band, %.6f for R, %.4e for cov, %.3f
    for chi2)."""
    assert c is not None, where
    d = p.to_dict()
    assert set(c) <= set(d), where
    for k, n in (("t", 3), ("R", 9), ("cov", 36), ("elevation_band", 2)):
        assert len(d[k]) == len(c[k]) == n, (where, k)
    for k in ("t", "elevation_band"):
        assert all(abs(a - b) <= 6e-6 for a, b in zip(d[k], c[k])), (where, k)
    for k in ("range", "azimuth", "elevation", "residual_m"):
        assert abs(d[k] - c[k]) <= 6e-6, (where, k)
    assert all(abs(a - b) <= 6e-7 for a, b in zip(d["R"], c["R"])), (where, "R")
    assert all(abs(a - b) <= 6e-5 * abs(b) + 1e-30 for a, b in zip(d["cov"], c["cov"])), (where,
                                                                                        "cov")
    assert abs(d["chi2"] - c["chi2"]) <= 6e-4, (where, "chi2")
    assert d["flags"] == c["flags"], where


def test_pool_poses_same_as_c_tool(pool_frames, c_tool):
    lines = run_c_tool(c_tool, [p for p, _ in pool_frames], ["--pose"])
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, **GEOMETRY)
    n = 0
    for (path, frame), line in zip(pool_frames, lines):
        dets = det.detect(frame)
        assert len(dets) == len(line["detections"]), path.name
        for d, c in zip(dets, line["detections"]):
            assert_pose_as_c(det.pose(d), c["pose"], path.name)
            # the module function with the same settings gives the same Pose
            assert pyactag.sonar_pose(d, tag_size=TAG_SIZE, family=FAMILY) == det.pose(d)
            n += 1
    assert n > 0


@pytest.mark.parametrize("extra,kw", [
    (["--vertical-aperture-deg", "20"], dict(vertical_aperture_deg=20)),
    (["--plane", "0,0,1,-1", "--plane-sd", "0.05", "--plane-tilt-deg", "2"],
     dict(plane=(0, 0, 1, -1), plane_sd=0.05, plane_tilt_deg=2)),
    (["--plane", "0.1,-0.2,3,-2.5", "--plane-tilt-deg", "1.5"],
     dict(plane=(0.1, -0.2, 3, -2.5), plane_tilt_deg=1.5)),
])
def test_example_pose_settings_same_as_c_tool(example_frame, c_tool, extra, kw):
    line = run_c_tool(c_tool, [EXAMPLE], ["--pose"] + extra)[0]
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, **GEOMETRY)
    dets = det.detect(example_frame)
    assert len(dets) == len(line["detections"]) == 1
    assert_pose_as_c(det.pose(dets[0], **kw), line["detections"][0]["pose"], str(extra))


def corners_of_pose(R, t, size):
    """(range, azimuth) of the inner square's corners TL TR BR BL of a tag
    at rotation R (rows, tag -> sonar) and centre t: the tag frame's x right,
    y down as printed (pose.h)."""
    h = 0.5 * size
    out = []
    for x, y in ((-h, -h), (h, -h), (h, h), (-h, h)):
        p = [t[i] + R[i][0] * x + R[i][1] * y for i in range(3)]
        out.append((math.sqrt(sum(v * v for v in p)), math.atan2(p[1], p[0])))
    return out


def face_toward(t, incidence_deg, turn_deg):
    """A rotation (rows, tag -> sonar) whose tag z (into the tag) makes
    incidence_deg with the line of sight to t (so the sonar sees the printed
    face), turned turn_deg about that normal."""
    def unit(v):
        n = math.sqrt(sum(x * x for x in v))
        return [x / n for x in v]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    los = unit(t)
    axis = unit(cross(los, [0.0, 0.0, 1.0]))
    a = math.radians(incidence_deg)
    # Rodrigues: los turned by a about axis (perpendicular to los)
    z = unit([los[i] * math.cos(a) + cross(axis, los)[i] * math.sin(a) for i in range(3)])
    x0 = unit(cross(axis, z))
    y0 = cross(z, x0)
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    x = [c * x0[i] + s * y0[i] for i in range(3)]
    y = cross(z, x)
    return [[x[i], y[i], z[i]] for i in range(3)]


def test_synthetic_pose_with_known_plane():
    # A tag at 2 m, 10 degrees to the left, 3 degrees below the sonar's
    # plane, seen at 60 degrees of incidence: exact corners and its own
    # plane known to 1 mm give the pose back, for the handedness the
    # corners wind in (the other one is flagged mirror_conflict).
    el, az, rng = math.radians(-3), math.radians(10), 2.0
    t = [rng * math.cos(el) * math.cos(az), rng * math.cos(el) * math.sin(az), rng * math.sin(el)]
    R = face_toward(t, 60.0, 25.0)
    n = [R[i][2] for i in range(3)]  # the face normal (tag z) in the sonar frame
    assert sum(n[i] * t[i] for i in range(3)) > 0  # z into the tag points away
    corners = corners_of_pose(R, t, TAG_SIZE)
    d = sum(n[i] * t[i] for i in range(3))
    good = 0
    for mirrored in (False, True):
        p = pyactag.sonar_pose(corners, mirrored, tag_size=TAG_SIZE, plane=n + [d],
                               plane_sd=0.001, plane_tilt_deg=0.05)
        if "mirror_conflict" in p.flags:
            continue
        assert all(abs(p.t[i] - t[i]) < 2e-3 for i in range(3)), (p.t, t)
        assert abs(p.elevation_rad - el) < 2e-3
        angle = math.acos(max(-1.0, min(1.0, (sum(p.R[i][j] * R[i][j] for i in range(3)
                                                    for j in range(3)) - 1) / 2)))
        assert angle < 0.01, angle
        assert p.residual_m < 1e-3
        good += 1
    assert good == 1


def test_degenerate_flag_and_pickle():
    # all four corners at one range: the image of the tag is a line
    corners = [(1.0, 0.05), (1.0, 0.02), (1.0, -0.01), (1.0, -0.04)]
    p = pyactag.sonar_pose(corners, False, tag_size=TAG_SIZE)
    assert "degenerate" in p.flags and p.flag_bits & 1
    q = pickle.loads(pickle.dumps(p))
    assert q == p and q.flags == p.flags
    assert len(p.R) == 3 and len(p.cov) == 6 and all(len(r) == 6 for r in p.cov)
    assert len(p.position_sd) == 3 and len(p.rotation_sd) == 3
    assert pyactag.POSE_FLAGS[0] == "degenerate" and len(pyactag.POSE_FLAGS) == 6


GOOD = [(1.10, 0.03), (1.20, -0.02), (1.19, -0.08), (1.09, -0.03)]


@pytest.mark.parametrize("kw,exc,words", [
    (dict(tag_size=0.0), ValueError, "tag_size"),
    (dict(tag_size=2e4), ValueError, "tag_size"),
    (dict(tag_size=True), TypeError, "tag_size"),
    (dict(tag_size=float("nan")), ValueError, "tag_size"),
    (dict(vertical_aperture_deg=0), ValueError, "vertical_aperture_deg"),
    (dict(vertical_aperture_deg=180), ValueError, "vertical_aperture_deg"),
    (dict(vertical_aperture=4.0), ValueError, "vertical_aperture"),
    (dict(vertical_aperture=0.2, vertical_aperture_deg=12), ValueError, "not both"),
    (dict(extent=0.5), ValueError, "extent"),
    (dict(range_sd=0.0), ValueError, "range_sd"),
    (dict(azimuth_sd=-1.0), ValueError, "azimuth_sd"),
    (dict(azimuth_sd="0.1"), TypeError, "azimuth_sd"),
    (dict(max_iterations=0), ValueError, "max_iterations"),
    (dict(max_iterations=101), ValueError, "max_iterations"),
    (dict(max_iterations=2.5), TypeError, "max_iterations"),
    (dict(plane=(0, 0, 0, -1), plane_sd=0.1), ValueError, "normal"),
    (dict(plane=(0, 0, 1, -1)), ValueError, "plane_sd"),
    (dict(plane=(0, 0, 1, -2e4), plane_sd=0.1), ValueError, "10000 m"),
    (dict(plane=(0, 0, 1), plane_sd=0.1), ValueError, "4 numbers"),
    (dict(plane=(0, 0, 1, float("inf")), plane_sd=0.1), ValueError, "plane[3]"),
    (dict(plane_sd=0.1), ValueError, "need plane"),
    (dict(plane=(0, 0, 1, -1), plane_sd=-0.1), ValueError, "negative"),
    (dict(plane=(0, 0, 1, -1), plane_tilt_deg=1e-20), ValueError, "plane_tilt_deg"),
    (dict(family="NoSuchFamily"), Exception, "NoSuchFamily"),
])
def test_bad_arguments_named(kw, exc, words):
    args = dict(tag_size=TAG_SIZE)
    args.update(kw)
    with pytest.raises(exc) as e:
        pyactag.sonar_pose(GOOD, False, **args)
    assert words in str(e.value), str(e.value)


@pytest.mark.parametrize("corners,mirrored,exc,words", [
    (GOOD[:3], False, ValueError, "4 (range_m, azimuth_rad) pairs"),
    ([(1.0, 0.0, 0.0)] * 4, False, ValueError, "pairs"),
    ("abcd", False, TypeError, "corners"),
    ([(0.0, 0.0)] + GOOD[1:], False, ValueError, "corners[0] range"),
    (GOOD[:3] + [(1.0, 20.0)], False, ValueError, "corners[3] azimuth"),
    (GOOD[:3] + [(1.0, "x")], False, TypeError, "corners[3] azimuth"),
    (GOOD, None, TypeError, "mirrored"),
    (GOOD, 1, TypeError, "mirrored"),
])
def test_bad_corners_named(corners, mirrored, exc, words):
    with pytest.raises(exc) as e:
        pyactag.sonar_pose(corners, mirrored, tag_size=TAG_SIZE)
    assert words in str(e.value), str(e.value)


def test_detection_and_mirrored_not_both(example_frame):
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, **GEOMETRY)
    d = det.detect(example_frame)[0]
    with pytest.raises(TypeError, match="mirrored"):
        pyactag.sonar_pose(d, True, tag_size=TAG_SIZE)
    with pytest.raises(TypeError, match="tag_size"):
        det.pose(d, tag_size=0.2)
    # the detection's own corners and flag, passed by hand, give the same pose
    assert det.pose(d) == pyactag.sonar_pose(d.corners_polar, d.mirrored, tag_size=TAG_SIZE)


def test_core_refuses_what_the_library_refuses():
    # _core.sonar_pose without the Python checks: the library's error, no crash
    with pytest.raises(pyactag.ActagError) as e:
        pyactag._core.sonar_pose([0.0] * 4, [0.0] * 4, False, None, TAG_SIZE, 0.2, None, None,
                                 None, 20, None, 0.0, 0.0)
    assert e.value.name == "ACTAG_ERR_PARAM"
    with pytest.raises(ValueError, match="4 numbers"):
        pyactag._core.sonar_pose([1.0] * 3, [0.0] * 4, False, None, TAG_SIZE, 0.2, None, None,
                                 None, 20, None, 0.0, 0.0)


@pytest.mark.parametrize("kw,exc,words", [
    # values a double holds but the library's float does not (review): named
    (dict(range_sd=1e39), ValueError, "range_sd"),
    (dict(azimuth_sd=3.2e38), ValueError, "azimuth_sd"),
    (dict(vertical_aperture_deg=179.9999999), ValueError, "vertical_aperture_deg"),
    (dict(vertical_aperture=math.pi - 1e-9), ValueError, "vertical_aperture"),
    (dict(plane=(0, 0, 1, -1), plane_sd=1e39), ValueError, "plane_sd"),
    (dict(plane=(0, 0, 1, -1), plane_tilt_deg=1e41), ValueError, "plane_tilt_deg"),
    (dict(plane=(0, 0, 1, -1), plane_sd=1e-21), ValueError, "plane_sd"),
    (dict(plane=(0, 0, 1, -1), plane_tilt_deg=1e-18), ValueError, "plane_tilt_deg"),
    (dict(tag_size=10 ** 400), OverflowError, "tag_size"),
    # the default outline, 7/3 tag sizes for 24 bits, must stay within 10000 m
    (dict(tag_size=5000.0), ValueError, "outline"),
    # an offset just beyond 10000 m as the library computes it from its floats
    (dict(plane=(0, 0, 1, 10000.01), plane_sd=0.1), ValueError, "10000 m"),
])
def test_float_limits_named(kw, exc, words):
    args = dict(tag_size=TAG_SIZE)
    args.update(kw)
    with pytest.raises(exc) as e:
        pyactag.sonar_pose(GOOD, False, **args)
    assert words in str(e.value), str(e.value)


def test_corner_float_limits_named():
    with pytest.raises(ValueError, match=r"corners\[3\] azimuth"):
        pyactag.sonar_pose(GOOD[:3] + [(1.0, 4 * math.pi - 1e-8)], False, tag_size=TAG_SIZE)
    with pytest.raises(OverflowError, match=r"corners\[3\] range"):
        pyactag.sonar_pose(GOOD[:3] + [(10 ** 400, 0.0)], False, tag_size=TAG_SIZE)


@pytest.mark.parametrize("extra,kw", [
    (["--plane-sd", "1e-18"], dict(plane_sd=1e-18)),
    (["--plane-tilt-deg", "1e-16"], dict(plane_tilt_deg=1e-16)),
])
def test_tiny_plane_sds_as_the_tool(example_frame, c_tool, extra, kw):
    # the tool's limits (1e-19 m, 1e-17 degrees), not stricter ones
    line = run_c_tool(c_tool, [EXAMPLE], ["--pose", "--plane", "0,0,1,-1"] + extra)[0]
    det = pyactag.Detector(FAMILY, tag_size=TAG_SIZE, **GEOMETRY)
    d = det.detect(example_frame)[0]
    assert_pose_as_c(det.pose(d, plane=(0, 0, 1, -1), **kw), line["detections"][0]["pose"],
                     str(extra))


def test_float_limits_accepted_as_the_library():
    # values the library takes are taken: tag_size 1e4 with no outline,
    # the smallest usable sds, an offset that rounds to 10000 m
    assert pyactag.sonar_pose(GOOD, False, tag_size=1e4, family=None) is not None
    pyactag.sonar_pose(GOOD, False, tag_size=TAG_SIZE, range_sd=5.8e-20, azimuth_sd=5.8e-20)
    pyactag.sonar_pose(GOOD, False, tag_size=TAG_SIZE, plane=(0, 0, 1, -1), plane_sd=5.8e-20)
    pyactag.sonar_pose(GOOD, False, tag_size=TAG_SIZE, plane=(0, 0, 1, -1), plane_tilt_deg=5e-18)
    pyactag.sonar_pose(GOOD, False, tag_size=TAG_SIZE, plane=(0, 0, 1, 10000.0002), plane_sd=0.1)
