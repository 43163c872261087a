"""sonar_pose / Detector.pose: the same poses as actag_detect --json --pose
(every pool frame, the example, a known plane, other settings), synthetic
corners of a known pose, the flags, and every bad argument named.
camera_pose: the frame conversion, the reprojection figures, the covariance
against a brute-force one computed here, its scaling, and every bad
argument named."""
import math
import pickle
import random

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


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def face_toward(t, incidence_deg, turn_deg):
    """A rotation (rows, tag -> sonar) whose tag z (into the tag) makes
    incidence_deg with the line of sight to t (so the sonar sees the printed
    face), turned turn_deg about that normal."""
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


# ---------------------------------------------------------------- camera pose
#
# The reference below is pure Python in double (numpy stays optional): the
# pinhole projection of the tag's corners, the pose moved by an error vector
# (dt, w) as pose.h defines it (t + dt, exp([w]x) R, sensor axes), the
# Jacobian by central differences and pixel_sd^2 (J^T J)^-1 by Gauss-Jordan,
# as tests/test_pose.c's cam_project, cam_move, cam_jacobian and
# cam_cov_reference do in C.

CAM = dict(fx=800.0, fy=760.0, cx=319.5, cy=239.5)
# sensor = C_OPT optical (pose.h: x = z_opt, y = -x_opt, z = -y_opt)
C_OPT = ((0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0))
TAG_CORNERS = ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))  # TL TR BR BL, tag sizes


def mat_mul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(A):
    return [[A[j][i] for j in range(3)] for i in range(3)]


def mat_vec(A, v):
    return [sum(A[i][k] * v[k] for k in range(3)) for i in range(3)]


def rodrigues(w):
    """exp([w]x), rows."""
    th = math.sqrt(sum(v * v for v in w))
    if th < 1e-15:
        return [[float(i == j) for j in range(3)] for i in range(3)]
    k = [v / th for v in w]
    s, c = math.sin(th), math.cos(th)
    K = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]]
    return [[(i == j) * c + (1.0 - c) * k[i] * k[j] + s * K[i][j] for j in range(3)]
            for i in range(3)]


def sensor_pose(d, az, el, inc, phi, psi):
    """tests/test_pose.c's make_pose: a tag at range d, azimuth az,
    elevation el (sensor frame) whose face normal makes the angle inc with
    the line of sight, tilted about it by phi, turned about its normal by
    psi. -> (R rows tag -> sensor, t)."""
    h = [0.0, 0.0, 1.0]
    p = [math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)]
    a = unit(cross(p, h))
    b = cross(a, p)
    z = unit([math.cos(inc) * p[i] + math.sin(inc) * (math.cos(phi) * a[i] + math.sin(phi) * b[i])
              for i in range(3)])
    a = unit(cross(z, h))
    b = cross(z, a)
    x = [math.cos(psi) * a[i] + math.sin(psi) * b[i] for i in range(3)]
    y = cross(z, x)
    return [[x[i], y[i], z[i]] for i in range(3)], [d * v for v in p]


def to_optical(R, t):
    """A sensor-frame pose as the camera reports it: (C^T R, C^T t)."""
    Ct = transpose(C_OPT)
    return mat_mul(Ct, R), mat_vec(Ct, t)


def project_optical(R_opt, t_opt, size, cam=CAM):
    """The corners (x0, y0, .. x3, y3; px) of the tag at the optical-frame
    pose, and their depths."""
    uv, depth = [], []
    for cx_, cy_ in TAG_CORNERS:
        q = [R_opt[i][0] * cx_ * size + R_opt[i][1] * cy_ * size + t_opt[i] for i in range(3)]
        uv += [cam["cx"] + cam["fx"] * q[0] / q[2], cam["cy"] + cam["fy"] * q[1] / q[2]]
        depth.append(q[2])
    return uv, depth


def project_sensor(R, t, size, cam=CAM):
    """The same from a sensor-frame pose (x_opt = -y, y_opt = -z, z_opt = x)."""
    uv = []
    for cx_, cy_ in TAG_CORNERS:
        p = [R[i][0] * cx_ * size + R[i][1] * cy_ * size + t[i] for i in range(3)]
        assert p[0] > 0.0
        uv += [cam["cx"] + cam["fx"] * -p[1] / p[0], cam["cy"] + cam["fy"] * -p[2] / p[0]]
    return uv


def move(R, t, e):
    """The pose moved by the error vector e = (dt, w): (exp([w]x) R, t + dt)."""
    return mat_mul(rodrigues(e[3:]), R), [t[i] + e[i] for i in range(3)]


def projection_jacobian(R, t, size, h=1e-6):
    """d(uv)/d(dt, w), 8 rows of 6, by central differences."""
    J = [[0.0] * 6 for _ in range(8)]
    for k in range(6):
        e = [0.0] * 6
        e[k] = h
        up = project_sensor(*move(R, t, e), size)
        e[k] = -h
        um = project_sensor(*move(R, t, e), size)
        for i in range(8):
            J[i][k] = (up[i] - um[i]) / (2.0 * h)
    return J


def inverse(A):
    """A^-1 by Gauss-Jordan elimination with partial pivoting."""
    n = len(A)
    M = [list(A[i]) + [float(i == j) for j in range(n)] for i in range(n)]
    for j in range(n):
        piv = max(range(j, n), key=lambda i: abs(M[i][j]))
        M[j], M[piv] = M[piv], M[j]
        for i in range(n):
            if i != j:
                f = M[i][j] / M[j][j]
                M[i] = [a - f * b for a, b in zip(M[i], M[j])]
    return [[M[i][n + j] / M[i][i] for j in range(n)] for i in range(n)]


def covariance_reference(R, t, size, sd):
    """pixel_sd^2 (J^T J)^-1 of the projection at (R, t)."""
    J = projection_jacobian(R, t, size)
    JtJ = [[sum(J[k][i] * J[k][j] for k in range(8)) for j in range(6)] for i in range(6)]
    return [[sd * sd * v for v in row] for row in inverse(JtJ)]


def camera_view(rng, inc0_deg, inc1_deg):
    """tests/test_pose.c's cam_view: a tag 0.4-4 m in front, within +-0.45
    rad of the axis across and +-0.35 up and down, at inc0..inc1 degrees of
    incidence, turned anyhow (sensor frame)."""
    d = rng.uniform(0.4, 4.0)
    az = rng.uniform(-0.45, 0.45)
    el = rng.uniform(-0.35, 0.35)
    inc = math.radians(rng.uniform(inc0_deg, inc1_deg))
    return sensor_pose(d, az, el, inc, rng.uniform(0.0, 6.283), rng.uniform(0.0, 6.283))


def test_camera_pose_frame_conversion():
    # a tag 2 m straight ahead, facing the camera, printed upright: R_opt = I
    p = pyactag.camera_pose([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0, 0, 2.0])
    assert p.t == (2.0, 0.0, 0.0)
    # tag z (into the tag) is forward, tag x (printed right) is right (-y),
    # tag y (printed down) is down (-z)
    assert p.R == ((0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0))
    assert p.flags == ("no_covariance",) and p.flag_bits == 16
    assert all(v == 0.0 for row in p.cov for v in row)
    assert (p.residual_m, p.chi2, p.iterations, p.elevation_band) == (0.0, 0.0, 0, (0.0, 0.0))
    # any pose: t = (z_opt, -x_opt, -y_opt), R's rows (R_opt's third, minus
    # its first, minus its second)
    R_opt = rodrigues([0.3, -0.5, 0.2])
    t_opt = [0.25, -0.4, 1.8]
    p = pyactag.camera_pose(R_opt, t_opt)
    want_t = (t_opt[2], -t_opt[0], -t_opt[1])
    want_R = (R_opt[2], [-v for v in R_opt[0]], [-v for v in R_opt[1]])
    assert all(abs(p.t[i] - want_t[i]) < 1e-6 for i in range(3)), p.t
    assert all(abs(p.R[i][j] - want_R[i][j]) < 1e-6 for i in range(3) for j in range(3)), p.R
    rng = math.sqrt(sum(v * v for v in want_t))
    assert abs(p.range_m - rng) < 1e-6
    assert abs(p.azimuth_rad - math.atan2(want_t[1], want_t[0])) < 1e-6
    assert abs(p.elevation_rad - math.asin(want_t[2] / rng)) < 1e-6
    # round trip: a sensor-frame pose as a co-located camera reports it
    R, t = sensor_pose(1.7, 0.2, 0.05, 0.7, 0.3, 1.1)
    p = pyactag.camera_pose(*to_optical(R, t))
    assert all(abs(p.R[i][j] - R[i][j]) < 1e-6 for i in range(3) for j in range(3))
    assert all(abs(p.t[i] - t[i]) < 1e-6 for i in range(3))
    assert abs(p.azimuth_rad - 0.2) < 1e-5 and abs(p.elevation_rad - 0.05) < 1e-5


def test_camera_pose_numpy_shapes_as_lists():
    # AprilTag's pose_R (3 x 3) and pose_t (3 x 1) as they come
    np = pytest.importorskip("numpy")
    R_opt = rodrigues([0.3, -0.5, 0.2])
    t_opt = [0.25, -0.4, 1.8]
    want = pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=0.3, **CAM)
    got = pyactag.camera_pose(np.array(R_opt), np.array(t_opt).reshape(3, 1), tag_size=TAG_SIZE,
                              pixel_sd=np.float64(0.3), **CAM)
    assert got == want
    uv, _ = project_optical(R_opt, t_opt, TAG_SIZE)
    assert (pyactag.camera_pose(np.array(R_opt), np.array(t_opt), tag_size=TAG_SIZE,
                                pixel_sd=0.3, corners=np.array(uv).reshape(4, 2), **CAM) ==
            pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=0.3,
                                corners=[uv[2 * i:2 * i + 2] for i in range(4)], **CAM))


def test_camera_reprojection_chi2_and_residual():
    R, t = sensor_pose(1.5, 0.1, -0.05, math.radians(20), 0.4, 0.9)
    R_opt, t_opt = to_optical(R, t)
    uv, depth = project_optical(R_opt, t_opt, TAG_SIZE)
    sd = 0.5

    def pose_of(coords):
        return pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=sd,
                                   corners=[coords[2 * i:2 * i + 2] for i in range(4)], **CAM)

    p = pose_of(uv)
    assert p.flags == ()
    assert p.chi2 < 1e-3 and p.residual_m < 1e-6, (p.chi2, p.residual_m)
    # one coordinate 1 px off (corner 2's x): chi2 = 1 / sd^2, the residual
    # 1 px at that corner's depth over the 4 corners' RMS: depth / fx / 2
    moved = list(uv)
    moved[4] += 1.0
    q = pose_of(moved)
    assert abs(q.chi2 - 1.0 / sd ** 2) < 0.01, q.chi2
    assert abs(q.residual_m - depth[2] / CAM["fx"] / 2.0) < 1e-6, q.residual_m
    # every coordinate 1 px off: 8 / sd^2 (the pose is not refitted)
    q = pose_of([v + 1.0 for v in uv])
    assert abs(q.chi2 - 8.0 / sd ** 2) < 0.05, q.chi2
    # the corners leave the covariance alone
    assert q.cov == p.cov == pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=sd,
                                                 **CAM).cov


def test_camera_covariance_matches_brute_force():
    # random views at 0-65 degrees of incidence and pixel_sd 0.1-2, the
    # reference at the pose the library holds (its floats); entries compared
    # relative to the product of their sds (a sign or axis slip in the
    # rotation columns gives errors of order 1)
    rng = random.Random(41)
    worst = 0.0
    for _ in range(30):
        R_opt, t_opt = to_optical(*camera_view(rng, 0.0, 65.0))
        sd = rng.uniform(0.1, 2.0)
        p = pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=sd, **CAM)
        assert p.flags == (), p.flags
        C = covariance_reference(p.R, p.t, TAG_SIZE, sd)
        for i in range(6):
            for j in range(6):
                rel = abs(p.cov[i][j] - C[i][j]) / math.sqrt(C[i][i] * C[j][j])
                worst = max(worst, rel)
                assert rel < 1e-3, (i, j, p.cov[i][j], C[i][j])
    assert worst > 0.0  # the comparison compared something


def test_camera_covariance_scales_and_is_symmetric():
    R_opt, t_opt = to_optical(*sensor_pose(2.2, -0.2, 0.1, math.radians(35), 1.2, 0.3))
    a = pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=0.2, **CAM)
    b = pyactag.camera_pose(R_opt, t_opt, tag_size=TAG_SIZE, pixel_sd=0.8, **CAM)
    for i in range(6):
        assert a.cov[i][i] > 0.0
        for j in range(6):
            scale = math.sqrt(a.cov[i][i] * a.cov[j][j])
            assert abs(b.cov[i][j] - 16.0 * a.cov[i][j]) <= 1e-5 * 16.0 * scale, (i, j)
            assert abs(a.cov[i][j] - a.cov[j][i]) <= 1e-6 * scale, (i, j)
            assert abs(b.cov[i][j] - b.cov[j][i]) <= 1e-6 * 16.0 * scale, (i, j)
    assert all(abs(y - 4.0 * x) <= 1e-5 * y for x, y in zip(a.position_sd, b.position_sd))
    assert all(abs(y - 4.0 * x) <= 1e-5 * y for x, y in zip(a.rotation_sd, b.rotation_sd))


def test_camera_behind_is_degenerate_not_an_error():
    R_opt, t_opt = to_optical(*sensor_pose(1.5, 0.1, -0.05, math.radians(20), 0.4, 0.9))
    uv, _ = project_optical(R_opt, t_opt, TAG_SIZE)
    corners = [uv[2 * i:2 * i + 2] for i in range(4)]
    p = pyactag.camera_pose(R_opt, [-v for v in t_opt], tag_size=TAG_SIZE, pixel_sd=0.5,
                            corners=corners, **CAM)
    assert set(p.flags) == {"degenerate", "no_covariance"}
    assert all(v == 0.0 for row in p.cov for v in row)
    assert p.chi2 == 0.0 and p.residual_m == 0.0  # nothing projected, nothing measured
    q = pickle.loads(pickle.dumps(p))
    assert q == p and q.to_dict()["flags"] == ["degenerate", "no_covariance"]


ROT = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
CAM_KW = dict(tag_size=TAG_SIZE, pixel_sd=0.5, **CAM)
CORNERS_PX = [(300.0, 220.0), (340.0, 220.0), (340.0, 260.0), (300.0, 260.0)]


@pytest.mark.parametrize("kw,exc,words", [
    (dict(pixel_sd=0.0), ValueError, "pixel_sd"),
    (dict(pixel_sd=-0.5), ValueError, "pixel_sd"),
    (dict(pixel_sd=float("nan")), ValueError, "pixel_sd"),
    (dict(pixel_sd=float("inf")), ValueError, "pixel_sd"),
    (dict(pixel_sd=1001.0), ValueError, "pixel_sd"),
    (dict(pixel_sd=9e-7), ValueError, "pixel_sd"),
    (dict(pixel_sd=True), TypeError, "pixel_sd"),
    (dict(pixel_sd="0.5"), TypeError, "pixel_sd"),
    (dict(tag_size=0.0), ValueError, "tag_size"),
    (dict(tag_size=2e4), ValueError, "tag_size"),
    (dict(tag_size=False), TypeError, "tag_size"),
    (dict(fx=0.5), ValueError, "fx"),
    (dict(fx=2e6), ValueError, "fx"),
    (dict(fy=float("nan")), ValueError, "fy"),
    (dict(fy=True), TypeError, "fy"),
    (dict(cx=2e5), ValueError, "cx"),
    (dict(cy=-2e5), ValueError, "cy"),
    (dict(cy=None), TypeError, "missing: cy"),
    (dict(pixel_sd=None, tag_size=None), TypeError, "missing: tag_size, pixel_sd"),
    (dict(tag_size=10 ** 400), OverflowError, "tag_size"),
    (dict(corners=CORNERS_PX[:3]), ValueError, "4 (x, y) pixel pairs"),
    (dict(corners=[(1.0, 2.0, 3.0)] * 4), ValueError, "4 (x, y) pixel pairs"),
    (dict(corners="abcd"), TypeError, "corners"),
    (dict(corners=[1.0] * 8), TypeError, "corners"),
    (dict(corners=CORNERS_PX[:3] + [(2e7, 0.0)]), ValueError, "corners[3] x"),
    (dict(corners=CORNERS_PX[:3] + [(0.0, float("nan"))]), ValueError, "corners[3] y"),
    (dict(corners=CORNERS_PX[:3] + [(0.0, True)]), TypeError, "corners[3] y"),
])
def test_camera_bad_arguments_named(kw, exc, words):
    args = dict(CAM_KW)
    args.update(kw)
    with pytest.raises(exc) as e:
        pyactag.camera_pose(ROT, [0.0, 0.0, 2.0], **args)
    assert words in str(e.value), str(e.value)


@pytest.mark.parametrize("R_opt,t_opt,exc,words", [
    (ROT[:2], [0, 0, 2], ValueError, "R_opt"),
    ([[1, 0], [0, 1], [0, 0]], [0, 0, 2], ValueError, "R_opt"),
    ([1, 0, 0, 0, 1, 0, 0, 0, 1], [0, 0, 2], TypeError, "R_opt"),
    ("abc", [0, 0, 2], TypeError, "R_opt"),
    (["100", "010", "001"], [0, 0, 2], TypeError, "R_opt"),
    ([[1, 0, 0], [0, 1, 0], [0, 0, float("nan")]], [0, 0, 2], ValueError, "R_opt[2][2]"),
    ([[1, 0, 0], [0, True, 0], [0, 0, 1]], [0, 0, 2], TypeError, "R_opt[1][1]"),
    ([[1, 0, 0], [0, 1, 0], [0, 0, -1]], [0, 0, 2], ValueError, "rotation"),  # a reflection
    ([[1.01, 0, 0], [0, 1, 0], [0, 0, 1]], [0, 0, 2], ValueError, "rotation"),
    (ROT, [0, 0], ValueError, "t_opt"),
    (ROT, [[0, 0, 2]], ValueError, "t_opt"),  # a 1 x 3 row
    (ROT, [[0, 1], [0, 1], [2, 1]], ValueError, "t_opt"),
    (ROT, 2.0, TypeError, "t_opt"),
    (ROT, "xyz", TypeError, "t_opt"),
    (ROT, [0, 0, 2e4], ValueError, "t_opt[2]"),
    (ROT, [0, float("inf"), 2], ValueError, "t_opt[1]"),
    (ROT, [0, False, 2], TypeError, "t_opt[1]"),
])
def test_camera_bad_pose_named(R_opt, t_opt, exc, words):
    with pytest.raises(exc) as e:
        pyactag.camera_pose(R_opt, t_opt)
    assert words in str(e.value), str(e.value)


def test_camera_limits_accepted_as_the_library():
    # the bounds themselves are taken (pose.h: inclusive, on the floats)
    for kw in (dict(pixel_sd=1e-6), dict(pixel_sd=1e3), dict(fx=1.0, fy=1e6),
               dict(cx=-1e5, cy=1e5), dict(tag_size=1e-3), dict(tag_size=1e4)):
        args = dict(CAM_KW)
        args.update(kw)
        p = pyactag.camera_pose(ROT, [0.0, 0.0, 2.0], **args)
        assert "no_covariance" not in p.flags or "degenerate" in p.flags, kw
    pyactag.camera_pose(ROT, [1e4, -1e4, 1e4], corners=[(1e7, -1e7)] * 4, **CAM_KW)
    assert pyactag.POSE_PIXEL_SD_MIN == pytest.approx(1e-6) and pyactag.POSE_PIXEL_SD_MAX == 1e3


def test_camera_corners_need_the_covariance():
    with pytest.raises(TypeError, match="corners need"):
        pyactag.camera_pose(ROT, [0, 0, 2], corners=CORNERS_PX)


def test_camera_core_refuses_what_the_library_refuses():
    # _core.camera_pose without the Python checks: the library's error, no crash
    core = pyactag._core.camera_pose
    R, t, cam = [1.0, 0, 0, 0, 1, 0, 0, 0, 1], [0.0, 0.0, 2.0], [800, 760, 319.5, 239.5, 0.5,
                                                                   TAG_SIZE]
    corners = [v for c in CORNERS_PX for v in c]
    assert len(core(R, t, cam, corners)) == 12
    bad_calls = [
        (R[:4] + [float("nan")] + R[5:], t, None, None),
        (R[:4] + [1e39] + R[5:], t, None, None),  # inf as a float
        (R, [0.0, 0.0, 2e4], None, None),
        (R, [0.0, float("-inf"), 2.0], None, None),
    ]
    nan, inf = float("nan"), float("inf")
    bad_camera = {  # fx, fy, cx, cy, pixel_sd, tag_size: values outside pose.h's bounds
        0: (0.5, 2e6, nan, inf, 1e39),
        1: (0.0, -760.0, nan, -inf),
        2: (2e5, -2e5, nan, 1e39),
        3: (2e5, -2e5, nan, -inf),
        4: (0.0, -0.5, 2e3, 5e-7, 1e-30, nan, inf),
        5: (0.0, 2e4, -1.0, 1e-30, nan, 1e39),
    }
    for k, vals in bad_camera.items():
        for v in vals:
            c = list(cam)
            c[k] = v
            bad_calls.append((R, t, c, None))
    for v in (float("nan"), 2e7, -1e39, float("inf")):
        bad_calls.append((R, t, cam, corners[:3] + [v] + corners[4:]))
    for args in bad_calls:
        with pytest.raises(pyactag.ActagError) as e:
            core(*args)
        assert e.value.name == "ACTAG_ERR_PARAM", args
    for args, exc, words in [
        ((R[:8], t, None, None), ValueError, "9 numbers"),
        ((R, t + [1.0], None, None), ValueError, "3 numbers"),
        ((R, t, cam[:5], None), ValueError, "6 numbers"),
        ((R, t, cam, corners[:7]), ValueError, "8 numbers"),
        ((R, t, None, corners), ValueError, "corners need camera"),
        ((1.0, t, None, None), TypeError, "R_opt"),
        ((R, t, cam, "abcdefgh"), TypeError, "corners[0]"),
        ((R, [0.0, True, 2.0], None, None), TypeError, "t_opt[1]"),
        ((R, t, cam[:4] + [True, TAG_SIZE], None), TypeError, "camera[4]"),
        ((R, t, None), TypeError, "camera_pose"),
    ]:
        with pytest.raises(exc) as e:
            core(*args)
        assert words in str(e.value), (args, str(e.value))


def test_camera_core_survives_garbage():
    # awkward values in random slots (R_opt no rotation either): a 12-tuple
    # without NaNs, or ActagError; both happen
    core = pyactag._core.camera_pose
    values = [0.0, -0.0, 1.0, -1.0, 0.5, 1e-30, 1e-45, 3e38, 3.4e38, 1e39, -1e39, 1e7, 1e300,
              float("nan"), float("inf"), float("-inf")]
    rng = random.Random(7)

    def some(good):
        return [rng.choice(values) if rng.random() < 0.05 else v for v in good]

    outcomes = set()
    for _ in range(3000):
        R = some([rng.uniform(-1, 1) for _ in range(9)])
        t = some([rng.uniform(-5, 5) for _ in range(3)])
        cam = some([800.0, 760.0, 319.5, 239.5, 0.5, TAG_SIZE])
        corners = some([rng.uniform(-1e3, 1e3) for _ in range(8)])
        with_cam = rng.random() < 0.8
        with_corners = with_cam and rng.random() < 0.5
        try:
            r = core(R, t, cam if with_cam else None, corners if with_corners else None)
        except pyactag.ActagError as e:
            assert e.name == "ACTAG_ERR_PARAM"
            outcomes.add("error")
            continue
        assert len(r) == 12
        assert not any(v != v for v in r[0] + r[1] + r[2] + r[3:10]), r  # never a NaN
        outcomes.add("pose")
    assert outcomes == {"error", "pose"}
