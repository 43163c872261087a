"""The tag's 6-DOF pose in the sonar frame from one detection, and a camera's
pose of the same tag in the same frame convention with its covariance (C:
actag/pose.h).

    det = pyactag.Detector("AcTag24h10", tag_size=0.130628571,
                           min_range=0.1, max_range=1.5, aperture_deg=60)
    for d in det.detect(frame):
        p = det.pose(d, vertical_aperture_deg=12)
        print(p.t, p.elevation_rad, p.position_sd, p.flags)

Sonar frame: x forward, y left, z up (metres); the tag's frame: x right, y
down as printed, z into the tag, origin at the centre of the inner white
square. A sonar loses the elevation, so it comes from the vertical aperture
(the tag must fit in it), the corners' small second-order cues and, when the
vehicle knows it, the plane the tag lies on (``plane``): the covariance says
how well each part is known. ``mirrored`` picks the side of the sonar's
horizontal plane.

``camera_pose`` turns a camera's pose of the tag (AprilTag's or OpenCV's
optical frame: x right, y down, z forward) into the same sensor frame (x
along the optical axis, y left, z up) and, given the intrinsics and the
corners' pixel noise, gives it the covariance the sonar's poses have.
"""
import math
import numbers
import struct

from . import _core
from ._args import as_bool, as_int, as_real
from ._record import SlotRecord

#: Flag names, bit 0 first: the names ``actag_detect --json --pose`` prints.
POSE_FLAGS = ("degenerate", "elevation", "not_converged", "mirror_conflict", "no_covariance",
              "plane")

#: The default corner noise of the covariance (pose.h): range (m), azimuth (rad).
POSE_RANGE_SD = _core.POSE_RANGE_SD
POSE_AZIMUTH_SD = _core.POSE_AZIMUTH_SD

#: The bounds of camera_pose's pixel_sd (px, inclusive; pose.h's
#: ACTAG_POSE_PIXEL_SD_MIN, _MAX as the library's floats).
POSE_PIXEL_SD_MIN = _core.POSE_PIXEL_SD_MIN
POSE_PIXEL_SD_MAX = _core.POSE_PIXEL_SD_MAX


class Pose(SlotRecord):
    """A tag's pose in the sonar frame (``actag_pose``), or in a camera's
    sensor frame (``camera_pose``: x along the optical axis, y left, z up;
    elevation_band (0.0, 0.0), iterations 0, residual_m and chi2 from the
    corners when given, else 0).

    Attributes:
        R: rotation tag -> sonar, 3 rows of 3.
        t: (x, y, z) of the tag centre, metres (x forward, y left, z up).
        cov: 6 x 6 covariance (6 rows) of (dt, w): the position error (m) and
            the rotation error vector (rad, R_true = exp([w]x) R).
        range_m, azimuth_rad, elevation_rad: of the centre.
        elevation_band: (lo, hi), radians: the centre elevations that keep
            the tag's outline inside the vertical aperture (lo > hi: none).
        residual_m: RMS distance of the measured from the fitted corners.
        chi2: sum of squared normalised corner residuals (about 3 expected).
        iterations: trial steps of the fit.
        flag_bits: the ``ACTAG_POSE_*`` bits; ``flags``: their names
            (``POSE_FLAGS``): degenerate (orientation unreliable), elevation
            (the tag cannot fit the aperture), not_converged,
            mirror_conflict (the corners' winding contradicts mirrored),
            no_covariance, plane (the fit left the known plane).
    """

    __slots__ = ("R", "t", "cov", "range_m", "azimuth_rad", "elevation_rad", "elevation_band",
                 "residual_m", "chi2", "iterations", "flag_bits")

    def __init__(self, R, t, cov, range_m, azimuth_rad, elevation_rad, elevation_band,
                 residual_m, chi2, iterations, flag_bits):
        self.R = R
        self.t = t
        self.cov = cov
        self.range_m = range_m
        self.azimuth_rad = azimuth_rad
        self.elevation_rad = elevation_rad
        self.elevation_band = elevation_band
        self.residual_m = residual_m
        self.chi2 = chi2
        self.iterations = iterations
        self.flag_bits = flag_bits

    @classmethod
    def _of_core(cls, r):
        R, t, cov, rng, az, el, lo, hi, res, chi2, its, flags = r
        return cls(tuple(R[3 * i:3 * i + 3] for i in range(3)), t,
                   tuple(cov[6 * i:6 * i + 6] for i in range(6)), rng, az, el, (lo, hi), res,
                   chi2, its, flags)

    @property
    def flags(self):
        """Names of the flags set (``POSE_FLAGS``), bit 0 first."""
        return tuple(n for i, n in enumerate(POSE_FLAGS) if self.flag_bits & (1 << i))

    @property
    def position_sd(self):
        """Standard deviations of x, y, z (m): the covariance's diagonal."""
        return tuple(math.sqrt(max(self.cov[i][i], 0.0)) for i in range(3))

    @property
    def rotation_sd(self):
        """Standard deviations of the rotation error vector (rad)."""
        return tuple(math.sqrt(max(self.cov[i][i], 0.0)) for i in range(3, 6))

    def to_dict(self):
        """Plain dict (JSON-ready) with the keys of ``actag_detect --json
        --pose``'s "pose" member (R and cov flattened row by row) and one
        more, iterations."""
        return {
            "t": list(self.t),
            "R": [v for row in self.R for v in row],
            "range": self.range_m,
            "azimuth": self.azimuth_rad,
            "elevation": self.elevation_rad,
            "elevation_band": list(self.elevation_band),
            "cov": [v for row in self.cov for v in row],
            "residual_m": self.residual_m,
            "chi2": self.chi2,
            "flags": list(self.flags),
            "iterations": self.iterations,
        }

    def __repr__(self):
        return ("Pose(t=({:.4f}, {:.4f}, {:.4f}), elevation_rad={:.4f}, flags={})".format(
            self.t[0], self.t[1], self.t[2], self.elevation_rad, self.flags))


_FLT_MAX = 3.4028234663852886e38


def _f32(x):
    """x as the C float the library gets (beyond the float range: +-inf)."""
    try:
        return struct.unpack("f", struct.pack("f", x))[0]
    except OverflowError:
        return math.copysign(math.inf, x)


_PI32 = _f32(3.14159265)  # pose.c's P_PI
_AZ_LIMIT = _f32(4.0 * _PI32)  # pose.c: 4.0f * P_PI


def _p_finite(v):
    """pose.c's "finite": |v| < 3e38 (as a float)."""
    return v == v and -_f32(3.0e38) < v < _f32(3.0e38)


def _sd_usable(v):
    """pose.c's p_sd_ok on the float v: positive, finite, and 1 / v^2 a
    finite float (from about 5.5e-20 up)."""
    if not (_p_finite(v) and v > 0.0):
        return False
    sq = _f32(v * v)
    return sq > 0.0 and _p_finite(_f32(1.0 / sq))


def _lib_plane_offset(p32):
    """The plane's offset |d| / |n| as pose.c computes it from the four
    floats it gets (each step rounded to a float: divisions, products and
    the square root of floats, exact in double, then rounded, as the C
    float operations round them)."""
    big = max(abs(v) for v in p32[:3])
    n = [_f32(v / big) for v in p32[:3]]
    dot = _f32(_f32(_f32(n[0] * n[0]) + _f32(n[1] * n[1])) + _f32(n[2] * n[2]))
    return _f32(_f32(p32[3] / big) / _f32(math.sqrt(dot)))


def _finite(name, value):
    v = as_real(name, value)
    if not math.isfinite(v):
        raise ValueError("{} must be finite, got {!r}".format(name, value))
    return v


def _length(name, value, what):
    """A length the library takes (pose.h: 0.001 to 10000 m as a float)."""
    v = _finite(name, value)
    if not 1e-3 <= _f32(v) <= 1e4:
        raise ValueError("{} must be 0.001 to 10000 m{}, got {!r}".format(name, what, value))
    return v


def _positive_sd(name, value):
    v = _finite(name, value)
    if not _sd_usable(_f32(v)):
        raise ValueError("{} must be a standard deviation from about 5.5e-20 to 3e38 (pose.h), "
                         "got {!r}".format(name, value))
    return v


def _corners_of(corners, mirrored):
    """(ranges, azimuths, mirrored) of a Detection, or of 4 (range, azimuth)
    pairs and the mirrored flag."""
    if hasattr(corners, "corners_polar") and hasattr(corners, "mirrored"):
        if mirrored is not None:
            raise TypeError("mirrored comes from the detection; do not pass it as well")
        pairs, mirrored = corners.corners_polar, corners.mirrored
    else:
        if mirrored is None:
            raise TypeError("mirrored (bool) is required with corners given as (range, azimuth) "
                            "pairs")
        pairs = corners
    mirrored = as_bool("mirrored", mirrored)
    if isinstance(pairs, (str, bytes)):
        raise TypeError("corners must be 4 (range_m, azimuth_rad) pairs, got {!r}".format(pairs))
    try:
        pairs = [tuple(p) for p in pairs]
    except TypeError:
        raise TypeError("corners must be 4 (range_m, azimuth_rad) pairs, got {!r}".format(
            corners)) from None
    if len(pairs) != 4 or any(len(p) != 2 for p in pairs):
        raise ValueError("corners must be 4 (range_m, azimuth_rad) pairs in tag order (TL, TR, "
                         "BR, BL), got {!r}".format(corners))
    ranges = [_length("corners[{}] range".format(i), p[0], "") for i, p in enumerate(pairs)]
    azimuths = [as_real("corners[{}] azimuth".format(i), p[1]) for i, p in enumerate(pairs)]
    for i, a in enumerate(azimuths):
        if not -_AZ_LIMIT < _f32(a) < _AZ_LIMIT:
            raise ValueError("corners[{}] azimuth must lie within +-4 pi rad, got {!r}".format(
                i, pairs[i][1]))
    return ranges, azimuths, mirrored


def _plane_of(plane, plane_sd, plane_tilt_deg):
    """The plane as the library gets it (normalised as actag_detect --plane
    does: by the largest component, then to unit length, in double; the
    offset within pose.h's 10000 m) and its sds, checked as the library and
    the tool check them."""
    sd = _finite("plane_sd", plane_sd)
    tilt = _finite("plane_tilt_deg", plane_tilt_deg)
    if sd < 0.0 or tilt < 0.0:
        raise ValueError("plane_sd and plane_tilt_deg must not be negative, got {!r}, {!r}".format(
            plane_sd, plane_tilt_deg))
    if plane is None:
        if sd > 0.0 or tilt > 0.0:
            raise ValueError("plane_sd and plane_tilt_deg need plane=(nx, ny, nz, d)")
        return None, 0.0, 0.0
    if isinstance(plane, (str, bytes)):
        raise TypeError("plane must be (nx, ny, nz, d), got {!r}".format(plane))
    try:
        p = [_finite("plane[{}]".format(i), v) for i, v in enumerate(plane)]
    except TypeError as e:
        if "plane[" in str(e):
            raise
        raise TypeError("plane must be (nx, ny, nz, d), got {!r}".format(plane)) from None
    if len(p) != 4:
        raise ValueError("plane must be 4 numbers (nx, ny, nz, d: n . p = d in the sonar frame), "
                         "got {!r}".format(plane))
    if not (sd > 0.0 or tilt > 0.0):
        raise ValueError("plane needs plane_sd (m) and/or plane_tilt_deg above 0 (how well it "
                         "is known; a plane known exactly: give small ones, e.g. 0.001)")
    big = max(abs(v) for v in p[:3])
    if not big > 0.0:
        raise ValueError("plane: the normal ({}, {}, {}) must be non-zero".format(*p[:3]))
    u = [v / big for v in p]
    ns = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    unit = [v / ns for v in u]
    if not abs(_lib_plane_offset([_f32(v) for v in unit])) <= 1e4:
        raise ValueError("plane: the plane must lie within 10000 m of the sonar (pose.h), got "
                         "an offset of {:g} m".format(abs(u[3]) / ns))
    tilt_rad = tilt * math.pi / 180.0  # as actag_detect --plane-tilt-deg converts it
    # the tool's limits (pose.h: above 0 with 1 / sd^2 a float)
    if sd > 0.0 and not _sd_usable(_f32(sd)):
        raise ValueError("plane_sd must be 0, or from about 5.8e-20 to 3e38 m (pose.h), got "
                         "{!r}".format(plane_sd))
    if tilt > 0.0 and not _sd_usable(_f32(tilt_rad)):
        raise ValueError("plane_tilt_deg must be 0, or from about 3.4e-18 to 1.7e40 degrees "
                         "(pose.h), got {!r}".format(plane_tilt_deg))
    return unit, sd, tilt_rad


def sonar_pose(corners, mirrored=None, *, tag_size, vertical_aperture_deg=None,
               vertical_aperture=None, family="AcTag24h10", extent=None, range_sd=None,
               azimuth_sd=None, max_iterations=20, plane=None, plane_sd=0.0,
               plane_tilt_deg=0.0):
    """The tag's pose in the sonar frame from its four corners.

    ``corners``: a ``Detection`` (its ``corners_polar`` and ``mirrored``), or
    four (range_m, azimuth_rad) pairs in tag order (TL, TR, BR, BL) with
    ``mirrored`` given. Keywords:

    - ``tag_size``: side of the inner white square, metres (0.001 to 10000);
    - ``vertical_aperture_deg`` (or ``vertical_aperture`` in radians): the
      full width of the sonar's elevation fan, in (0, 180) degrees (default
      12 degrees, the paper's);
    - ``family``: a name or Family, for the tag's outline (whole tag side
      over the white square's, 7/3 for 24 bits) unless ``extent`` gives it
      (at least 1; ``family=None``: 1);
    - ``range_sd`` (m), ``azimuth_sd`` (rad): the corner noise behind the
      covariance (defaults ``POSE_RANGE_SD``, ``POSE_AZIMUTH_SD``, measured
      on the simulator);
    - ``max_iterations``: trial steps per pass, 1 to 100 (20);
    - ``plane=(nx, ny, nz, d)``: the plane n . p = d (sonar frame, metres)
      the tag's face lies on, as the vehicle knows it (a seabed at altitude
      H under an upright sonar: (0, 0, 1, -H)), with ``plane_sd`` (m, its
      offset's sd) and/or ``plane_tilt_deg`` (its tilt's sd) above 0: it
      pins the elevation one ping leaves free.

    Bad values raise TypeError, ValueError or OverflowError naming them,
    checked as the library checks the floats it gets. Returns a ``Pose``;
    degenerate geometry is no error but a flag (``Pose.flags``).
    """
    ranges, azimuths, mirrored = _corners_of(corners, mirrored)
    ts = _length("tag_size", tag_size, " (side of the inner white square)")
    if vertical_aperture_deg is not None and vertical_aperture is not None:
        raise ValueError("give vertical_aperture_deg or vertical_aperture (radians), not both")
    if vertical_aperture is not None:
        name, given = "vertical_aperture", vertical_aperture
        va = _finite(name, given)
        rule = "in (0, pi) rad"
    else:
        name = "vertical_aperture_deg"
        given = 12.0 if vertical_aperture_deg is None else vertical_aperture_deg
        va = _finite(name, given) * math.pi / 180.0  # as actag_detect converts it
        rule = "in (0, 180) degrees"
    if not 0.0 < _f32(va) < _PI32:  # pose.h, on the float the library gets
        raise ValueError("{} must be {} (as a float, below 3.14159265 rad), got {!r}".format(
            name, rule, given))
    fam = None
    if family is not None:
        from .detection import _family
        fam = _family(family)
    ext = None
    if extent is not None:
        ext = _finite("extent", extent)
        if not _f32(ext) >= 1.0:
            raise ValueError("extent must be at least 1 (tag sizes), got {!r}".format(extent))
        outline = _f32(ext)
    else:  # actag_pose_params_default's: the whole tag, (k+1)/(k-3) for 4k bits
        k = fam.bits // 4 if fam is not None and fam.bits >= 16 else 0
        outline = _f32(_f32(k + 1) / _f32(k - 3)) if k else 1.0
    if not _f32(outline * _f32(ts)) <= 1e4:  # pose.h: the outline's side at most 10000 m
        raise ValueError("tag_size x the outline's extent ({:g} tag sizes) must be at most "
                         "10000 m, got tag_size {!r}".format(outline, tag_size))
    rsd = None if range_sd is None else _positive_sd("range_sd", range_sd)
    asd = None if azimuth_sd is None else _positive_sd("azimuth_sd", azimuth_sd)
    its = as_int("max_iterations", max_iterations, 1, 100)
    pl, psd, ptilt = _plane_of(plane, plane_sd, plane_tilt_deg)
    return Pose._of_core(_core.sonar_pose(ranges, azimuths, mirrored, fam, ts, va, ext, rsd, asd,
                                          its, pl, psd, ptilt))


# actag_pose_camera_covariance's bounds (pose.h; exact as floats)
_MAX_FOCAL = 1e6  # px
_MAX_CENTRE = 1e5  # px, principal point
_MAX_PIXEL = 1e7  # px, a measured corner
_MAX_T = 1e4  # m, an entry of t
_ROTATION_TOL = 1e-3


def _in_range(name, value, lo, hi, rule):
    """A finite number whose float (what the library gets) lies in lo..hi."""
    v = _finite(name, value)
    if not lo <= _f32(v) <= hi:
        raise ValueError("{} must be {} (pose.h), got {!r}".format(name, rule, value))
    return v


def _grid(value, nrows, ncols, what):
    """value as nrows lists of ncols items (numbers checked by the caller):
    not a sequence of sequences (or strings in it) is a TypeError, other
    shapes a ValueError, each with ``what`` and the value."""
    if isinstance(value, (str, bytes)):
        raise TypeError("{}, got {!r}".format(what, value))
    try:
        rows = [r for r in value]
        if any(isinstance(r, (str, bytes)) for r in rows):
            raise TypeError
        rows = [list(r) for r in rows]
    except TypeError:
        raise TypeError("{}, got {!r}".format(what, value)) from None
    if len(rows) != nrows or any(len(r) != ncols for r in rows):
        raise ValueError("{}, got {!r}".format(what, value))
    return rows


def _matrix3(R_opt):
    """R_opt as 9 floats row by row: 3 rows of 3 finite numbers that form a
    rotation (orthonormal to 1e-3, determinant +1)."""
    rows = _grid(R_opt, 3, 3,
                 "R_opt must be 3 rows of 3 numbers (rotation tag -> camera, optical frame)")
    R = [[_finite("R_opt[{}][{}]".format(i, j), v) for j, v in enumerate(r)]
         for i, r in enumerate(rows)]
    worst = max(abs(sum(R[i][k] * R[j][k] for k in range(3)) - (i == j))
                for i in range(3) for j in range(3))
    det = (R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) -
           R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
           R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]))
    if not (worst <= _ROTATION_TOL and det > 0.0):
        raise ValueError("R_opt must be a rotation (orthonormal rows to {:g}, determinant +1), "
                         "got {!r}".format(_ROTATION_TOL, R_opt))
    return [v for r in R for v in r]


def _vector3(t_opt):
    """t_opt as 3 floats (m, each within +-10000 as the library's float): 3
    numbers, or a 3 x 1 column (AprilTag's pose_t, OpenCV's tvec)."""
    what = "t_opt must be 3 numbers or a 3 x 1 column (metres, optical frame)"
    if isinstance(t_opt, (str, bytes)):
        raise TypeError("{}, got {!r}".format(what, t_opt))
    try:
        items = list(t_opt)
    except TypeError:
        raise TypeError("{}, got {!r}".format(what, t_opt)) from None
    if len(items) != 3:
        raise ValueError("{}, got {!r}".format(what, t_opt))
    out = []
    for i, v in enumerate(items):
        if not isinstance(v, (numbers.Real, str, bytes)):
            try:
                row = list(v)  # a row of a 3 x 1 column: one number
            except TypeError:
                row = None  # as_real names it
            if row is not None:
                if len(row) != 1:
                    raise ValueError("{}, got {!r}".format(what, t_opt))
                v = row[0]
        out.append(_in_range("t_opt[{}]".format(i), v, -_MAX_T, _MAX_T, "within +-10000 m"))
    return out


def _pixels_of(corners):
    """8 floats (x0, y0, .. x3, y3) of 4 (x, y) pixel pairs, each within
    +-1e7 px as the library's float."""
    pairs = _grid(corners, 4, 2, "corners must be 4 (x, y) pixel pairs in tag order (top-left, "
                  "top-right, bottom-right, bottom-left as printed)")
    return [_in_range("corners[{}] {}".format(i, axis), v, -_MAX_PIXEL, _MAX_PIXEL,
                      "within +-1e7 px")
            for i, p in enumerate(pairs) for axis, v in zip("xy", p)]


def camera_pose(R_opt, t_opt, *, tag_size=None, fx=None, fy=None, cx=None, cy=None,
                pixel_sd=None, corners=None):
    """A camera's pose of the tag in the sensor frame the sonar's poses use,
    with their covariance when the camera is described.

    ``R_opt``, ``t_opt``: the pose in the optical frame of AprilTag and
    OpenCV (x right, y down, z forward): p_camera = R_opt p_tag + t_opt,
    R_opt 3 rows of 3 numbers (a rotation: orthonormal to 1e-3, determinant
    +1), t_opt 3 numbers or a 3 x 1 column, metres (each within +-10000).
    The tag frame is AprilTag's and the sonar pose's: origin at the centre
    of the inner white square, x toward the printed right edge, y toward the
    printed bottom, z into the tag. The result is in the sensor frame: x
    along the optical axis, y left, z up (x = z_opt, y = -x_opt, z =
    -y_opt); ``Pose.R`` maps tag -> sensor.

    The covariance (keywords, all six together or none):

    - ``tag_size``: side of the inner white square, metres (0.001 to 10000);
    - ``fx``, ``fy``: focal lengths, pixels (1 to 1e6);
    - ``cx``, ``cy``: principal point, pixels (within +-1e5), with the centre
      of the top-left pixel at (0, 0) (OpenCV's calibration; AprilTag's
      convention is 0.5 more);
    - ``pixel_sd``: sd of each measured corner coordinate, pixels
      (``POSE_PIXEL_SD_MIN`` .. ``POSE_PIXEL_SD_MAX``, 1e-6 to 1e3; about
      0.1 to 0.3 on sharp images: measure it for your camera and water);

    fill ``Pose.cov`` (6 x 6 of (dt, w) as the sonar's: the corners' pixel
    noise through the pinhole projection, to first order; distortion must
    have been removed). ``corners``, 4 (x, y) pixel pairs (within +-1e7) in
    tag order (top-left, top-right, bottom-right, bottom-left as printed,
    pixel centres at whole numbers: AprilTag's corners, det->p, reversed
    and minus 0.5 px, as actag_apriltag_corners_to_actag gives them), add
    ``residual_m`` (the corners' RMS reprojection error in metres at their
    depth) and ``chi2`` (the sum of their 8 squared reprojection errors
    over pixel_sd^2, about 2 expected).

    Without the six keywords the Pose has no covariance (flag
    ``no_covariance``). A corner of the tag not in front of the camera, or
    a singular projection, is no error: flags ``degenerate`` and
    ``no_covariance``. Bad values raise TypeError, ValueError or
    OverflowError naming them, checked as the library checks the floats it
    gets. Returns a ``Pose``.
    """
    R = _matrix3(R_opt)
    t = _vector3(t_opt)
    given = dict(tag_size=tag_size, fx=fx, fy=fy, cx=cx, cy=cy, pixel_sd=pixel_sd)
    missing = [k for k, v in given.items() if v is None]
    camera = None
    if len(missing) < len(given):
        if missing:
            raise TypeError("the covariance needs tag_size, fx, fy, cx, cy and pixel_sd: give "
                            "all six or none (missing: {})".format(", ".join(missing)))
        camera = [
            _in_range("fx", fx, 1.0, _MAX_FOCAL, "1 to 1e6 px"),
            _in_range("fy", fy, 1.0, _MAX_FOCAL, "1 to 1e6 px"),
            _in_range("cx", cx, -_MAX_CENTRE, _MAX_CENTRE, "within +-1e5 px"),
            _in_range("cy", cy, -_MAX_CENTRE, _MAX_CENTRE, "within +-1e5 px"),
            _in_range("pixel_sd", pixel_sd, POSE_PIXEL_SD_MIN, POSE_PIXEL_SD_MAX,
                      "1e-6 to 1e3 px"),
            _length("tag_size", tag_size, " (side of the inner white square)"),
        ]
    pixels = None
    if corners is not None:
        if camera is None:
            raise TypeError("corners need the covariance's tag_size, fx, fy, cx, cy and "
                            "pixel_sd")
        pixels = _pixels_of(corners)
    return Pose._of_core(_core.camera_pose(R, t, camera, pixels))
