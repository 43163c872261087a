"""Detection: ``detect()``, ``Detector`` and the ``Detection`` result."""

import itertools
import math
from collections import namedtuple

from . import _core
from ._args import as_bool, as_int, as_real
from ._record import SlotRecord
from ._arrays import array2d
from .families import Family

DEFAULT_FAMILY = "AcTag24h10"
DEFAULT_MAX_DETECTIONS = 64

#: Keyword arguments that describe the sonar (the rest are detection parameters).
GEOMETRY_KEYS = (
    "min_range",
    "max_range",
    "aperture",
    "aperture_deg",
    "bearings",
    "range_ascending",
    "azimuth_ascending",
)

#: Result of ``Detector.run()``: the detections, the pipeline's counters
#: (a dict of every field of the C ``actag_stats``, by its C name) and, with
#: ``stages=True``, the stage images {"filtered": median-filtered frame,
#: "binary": 0/255 threshold image}. The counters:
#:
#: - contours: outer borders traced; size_ok: those that passed the physical
#:   size filter; overflowed: borders longer than the point buffer (skipped);
#:   quads: quadrilaterals fitted; decoded: quads that decoded to a family
#:   member; duplicates: decodes dropped as the same tag seen twice; dropped:
#:   detections beyond max_detections; searched: structure-search candidates
#:   decoded;
#: - work done: decodes (decoder calls: quads, search, guesses), iterations
#:   (RANSAC iterations run);
#: - limits reached (``max_contours``, ``max_contour_iterations``,
#:   ``max_frame_iterations``, ``max_decodes``, ``search_candidates``):
#:   contour_cap (1 when the scan stopped at max_contours), ransac_exhausted
#:   (quad fits that ran all their iterations without an early exit),
#:   contour_budget (contours whose quad tries stopped at
#:   max_contour_iterations), frame_budget (quad fits skipped, or cut short
#:   (the lowered cap ran out), by max_frame_iterations), decode_cap (decoder calls skipped at
#:   max_decodes), search_cap (1 when candidates above search_min_score were
#:   left undecoded), guess_cap (contours given no extreme-point guess, 16 per
#:   frame at most).
Result = namedtuple("Result", ["detections", "stats", "stages"])

#: One corner of a detection: x_col = column and y_row = row (pixels,
#: sub-pixel, pixel centres at integers), range_m (metres), azimuth_rad.
Corner = namedtuple("Corner", ["x_col", "y_row", "range_m", "azimuth_rad"])


def default_params():
    """Every detection parameter with its C default (``actag_params_default``).

    ``max_bit_corrections`` None means automatic: min(3, the family's maximum).
    """
    return _core.default_params()


def tuning_names():
    """Names of the stage tuning fields (``actag_params.tuning`` in C), also
    accepted in a ``tuning`` dict; the other parameters are the user settings
    tag_size, max_bit_corrections, seed, min_margin and handedness."""
    return _core.tuning_names()


class Detection(SlotRecord):
    """One tag found in a frame.

    Attributes:
        id: tag ID in the family.
        hamming: number of corrected bits.
        decision_margin: how much better the reported code and orientation
            explain the cells than the next hypothesis (about 0 on noise,
            5-30 on a clear tag).
        mirrored: True when the sonar shows the tag mirrored (which side of
            the sonar's horizontal plane it lies on).
        inlier_ratio: RANSAC support of the quadrilateral.
        corners_xy: the inner white square's corners as printed, top-left,
            top-right, bottom-right, bottom-left, as (x, y) pixel pairs with
            x = COLUMN (beam) and y = ROW (range bin), sub-pixel, pixel
            centres at integers.
        corners_polar: the same corners as (range in metres, azimuth in
            radians) pairs.
    """

    __slots__ = ("id", "hamming", "mirrored", "decision_margin", "inlier_ratio", "corners_xy",
                 "corners_polar")

    def __init__(self, id, hamming, mirrored, decision_margin, inlier_ratio, corners_xy,
                 corners_polar):
        self.id = id
        self.hamming = hamming
        self.mirrored = mirrored
        self.decision_margin = decision_margin
        self.inlier_ratio = inlier_ratio
        self.corners_xy = corners_xy
        self.corners_polar = corners_polar

    @property
    def corners(self):
        """The four corners (tag order TL, TR, BR, BL) as ``Corner(x_col,
        y_row, range_m, azimuth_rad)``."""
        return tuple(Corner(x, y, r, a) for (x, y), (r, a) in zip(self.corners_xy,
                                                                   self.corners_polar))

    @property
    def corners_rowcol(self):
        """The corners as (row, column) pairs (the reference package's order)."""
        return tuple((y, x) for x, y in self.corners_xy)

    @property
    def ranges_m(self):
        """Range of each corner in metres."""
        return tuple(r for r, _ in self.corners_polar)

    @property
    def azimuths_rad(self):
        """Azimuth of each corner in radians."""
        return tuple(a for _, a in self.corners_polar)

    @property
    def center_xy(self):
        """Mean of the four corners, (x = column, y = row)."""
        return (sum(x for x, _ in self.corners_xy) / 4.0, sum(y for _, y in self.corners_xy) / 4.0)

    def to_dict(self):
        """Plain dict (JSON-ready) with the keys of ``actag_detect --json``
        (id, hamming, decision_margin, mirrored and corners as
        [{"x_col", "y_row", "range_m", "azimuth_rad"} x 4]) and one more,
        inlier_ratio (the RANSAC quad's, which the tool does not print)."""
        return {
            "id": self.id,
            "hamming": self.hamming,
            "decision_margin": self.decision_margin,
            "mirrored": self.mirrored,
            "inlier_ratio": self.inlier_ratio,
            "corners": [c._asdict() for c in self.corners],
        }

    def __repr__(self):
        return ("Detection(id={}, hamming={}, decision_margin={:.2f}, mirrored={}, "
                "corners_xy={})".format(self.id, self.hamming, self.decision_margin,
                                        self.mirrored,
                                        tuple((round(x, 2), round(y, 2))
                                              for x, y in self.corners_xy)))


def _family(family):
    # type(), not isinstance(): isinstance() believes a __class__ attribute
    # (a Mock(spec=Family) is no Family the C code could read).
    if issubclass(type(family), _core.Family):
        return family
    if issubclass(type(family), str):
        return Family(family)
    raise TypeError("family must be a name or a pyactag.Family, not {!r} ({})".format(
        family, type(family).__name__))


def _split_params(params, tuning):
    merged = dict(params)
    if tuning:
        names = set(_core.tuning_names())
        for k, v in dict(tuning).items():
            if k not in names:
                raise TypeError("'{}' is not a tuning field (pyactag.tuning_names()); pass it as "
                                "a keyword argument".format(k))
            if k in merged:
                raise TypeError("parameter '{}' given twice (keyword and tuning)".format(k))
            merged[k] = v
    return merged


#: The three forms of the horizontal field of view: one of them is given.
_APERTURE_FORMS = ("aperture", "aperture_deg", "bearings")


def _check_geometry(g):
    """Type checks of the geometry keywords given (None: not given)."""
    for k in ("min_range", "max_range", "aperture", "aperture_deg"):
        if g.get(k) is not None:
            as_real(k, g[k])
    for k in ("range_ascending", "azimuth_ascending"):
        if k in g:
            as_bool(k, g[k])
    bearings = g.get("bearings")
    if isinstance(bearings, (str, bytes)):
        raise TypeError("bearings must be a sequence of azimuths (radians), got {!r}".format(
            bearings))
    if g.get("aperture") is not None and g.get("aperture_deg") is not None:
        raise ValueError("give aperture (radians) or aperture_deg, not both")
    if bearings is not None and (g.get("aperture") is not None or
                                 g.get("aperture_deg") is not None):
        raise ValueError("sonar geometry: give aperture or bearings, not both")
    _check_bearings_order(bearings, g.get("azimuth_ascending", False))


def _check_bearings_order(bearings, azimuth_ascending):
    """azimuth_ascending is refused with bearings, not ignored (as by
    actag_detect --bearings): the table gives each column's azimuth."""
    if bearings is not None and as_bool("azimuth_ascending", azimuth_ascending):
        raise ValueError("sonar geometry: azimuth_ascending=True does not apply with bearings "
                         "(the table gives each column's azimuth in column order)")


def _geometry(base, overrides):
    for k in overrides:
        if k not in GEOMETRY_KEYS:
            raise TypeError("unknown sonar geometry keyword '{}'".format(k))
    _check_geometry(overrides)
    g = dict(base)
    # A field of view given for this frame replaces the stored one, whichever
    # form either is in; two forms in the same call stay an error.
    if any(overrides.get(k) is not None for k in _APERTURE_FORMS):
        for k in _APERTURE_FORMS:
            g[k] = None
    g.update(overrides)
    aperture = g.get("aperture")
    if aperture is not None:
        aperture = as_real("aperture", aperture)
    if g.get("aperture_deg") is not None:
        aperture = math.radians(as_real("aperture_deg", g["aperture_deg"]))
    if g.get("min_range") is None or g.get("max_range") is None:
        raise ValueError("sonar geometry: min_range and max_range (metres) are required")
    bearings = g.get("bearings")
    if bearings is None and aperture is None:
        raise ValueError("sonar geometry: give aperture (radians), aperture_deg, or bearings "
                         "(one azimuth per column)")
    _check_bearings_order(bearings, g.get("azimuth_ascending", False))
    return dict(min_range=as_real("min_range", g["min_range"]),
                max_range=as_real("max_range", g["max_range"]),
                aperture=aperture, bearings=bearings,
                range_ascending=as_bool("range_ascending", g.get("range_ascending", False)),
                azimuth_ascending=as_bool("azimuth_ascending", g.get("azimuth_ascending", False)))


def _stored_geometry(min_range, max_range, aperture, aperture_deg, bearings, range_ascending,
                     azimuth_ascending):
    """A constructor's default geometry, checked (Detector, Tracker)."""
    if bearings is not None and not isinstance(bearings, (str, bytes)):
        # kept as a tuple: an iterator or generator would be spent by the
        # first frame (a str is left for the C side to refuse)
        # (at most MAX_DIM + 1 values are drawn: no frame has more columns,
        # and an endless iterator would hang the constructor)
        try:
            it = iter(bearings)
        except TypeError:
            pass  # not iterable: the C side's TypeError names it
        else:
            bearings = tuple(itertools.islice(it, _core.MAX_DIM + 1))
            if len(bearings) > _core.MAX_DIM:
                raise ValueError("bearings has more than {} values, more than any frame has "
                                 "columns".format(_core.MAX_DIM))
    g = dict(min_range=min_range, max_range=max_range, aperture=aperture,
             aperture_deg=aperture_deg, bearings=bearings, range_ascending=range_ascending,
             azimuth_ascending=azimuth_ascending)
    _check_geometry(g)
    return g


def _max_detections(n):
    return as_int("max_detections", n, 0, _core.MAX_DETECTIONS)


class _Searcher:
    """What Detector and Tracker share: the C object (``_core``) with the
    family and parameters, the default geometry (``_geometry``), and the
    pose of what they found."""

    @property
    def family(self):
        """The Family."""
        return self._core.family

    @property
    def params(self):
        """The (whole-frame) parameters in use (a dict copy)."""
        return self._core.params

    @property
    def geometry(self):
        """The default sonar geometry (a dict copy)."""
        return dict(self._geometry)

    def _pose(self, corners, mirrored, options):
        """sonar_pose of corners (a Detection, or (range, azimuth) pairs with
        mirrored) with this object's family and tag_size."""
        from .pose import sonar_pose
        for k in ("family", "tag_size"):
            if k in options:
                raise TypeError("{} is the {}'s; use pyactag.sonar_pose for another".format(
                    k, type(self).__name__.lower()))
        return sonar_pose(corners, mirrored, family=self.family,
                          tag_size=self.params["tag_size"], **options)


class Detector(_Searcher):
    """Detection parameters, the sonar geometry and a reusable workspace.

    ``Detector(family="AcTag24h10", *, min_range, max_range, aperture |
    aperture_deg | bearings, range_ascending=False, azimuth_ascending=False,
    max_detections=64, tuning=None, **params)``

    Geometry (metres, radians): rows are range bins, columns beams. Default
    orientation: row 0 = max_range, column 0 = +aperture/2; the flags select
    the other ones. ``bearings`` is one azimuth per column (radians,
    strictly monotonic) instead of a uniform aperture; the table gives the
    column order, so ``azimuth_ascending=True`` with ``bearings`` is a
    ValueError (as ``actag_detect`` refuses the pair). Geometry given here
    is the default of every ``detect()`` call, which may override it: an
    ``aperture``, ``aperture_deg`` or ``bearings`` given to a call replaces
    the stored field of view, whichever of the three forms it was given in.
    Numbers must be real numbers and the flags bools (TypeError otherwise).

    ``params``: any name of ``default_params()``: the user settings
    ``tag_size`` (metres, side of the inner white square),
    ``max_bit_corrections``, ``seed``, ``min_margin``, and the stage tuning
    (``tuning_names()``: ``median_radius``, ``decode_mode`` ('fit' or
    'binary'), ...), which may also come as a dict, ``tuning``. Invalid values raise ActagError with the
    library's message.

    Threads: ``detect()`` releases the GIL. One Detector may be used from
    several threads at once (a call that finds the kept workspace busy uses
    its own).
    """

    def __init__(self, family=DEFAULT_FAMILY, *, max_detections=DEFAULT_MAX_DETECTIONS,
                 tuning=None, min_range=None, max_range=None, aperture=None, aperture_deg=None,
                 bearings=None, range_ascending=False, azimuth_ascending=False, **params):
        self._core = _core.Detector(_family(family), _split_params(params, tuning))
        self.max_detections = _max_detections(max_detections)
        self._geometry = _stored_geometry(min_range, max_range, aperture, aperture_deg, bearings,
                                          range_ascending, azimuth_ascending)

    def run(self, frame, *, stages=False, max_detections=None, **geometry):
        """Detect tags in ``frame``; returns ``Result(detections, stats, stages)``
        (``stats``: every counter of the C ``actag_stats``; see ``Result``).

        ``frame``: a 2-D uint8 or uint16 array or buffer (numpy arrays and
        strided views, memoryviews, Pillow images...), rows = range bins.
        ``geometry``: overrides of the constructor's sonar geometry.
        """
        g = _geometry(self._geometry, geometry)
        n = self.max_detections if max_detections is None else _max_detections(max_detections)
        raw, stats, images = self._core.detect(frame, g["min_range"], g["max_range"],
                                               g["aperture"], g["bearings"],
                                               g["range_ascending"], g["azimuth_ascending"], n,
                                               as_bool("stages", stages))
        dets = [Detection(*t) for t in raw]
        if images is not None:
            rows, cols = images["rows"], images["cols"]
            images = {k: array2d(images[k], rows, cols) for k in ("filtered", "binary")}
        return Result(dets, stats, images)

    def detect(self, frame, **geometry):
        """Detect tags in ``frame``; returns a list of ``Detection`` (see ``run``)."""
        return self.run(frame, **geometry).detections

    def pose(self, detection, **options):
        """The 6-DOF pose of one of this detector's detections in the sonar
        frame (``pyactag.sonar_pose`` with this detector's family and
        tag_size): ``det.pose(d, vertical_aperture_deg=12)``; ``options``:
        the keywords of ``sonar_pose`` (vertical aperture, noise, known
        plane). Returns a ``Pose``."""
        return self._pose(detection, None, options)

    def __reduce__(self):
        """Pickling (e.g. to worker processes): the family, every parameter,
        max_detections and the default geometry; the copy has its own
        workspace."""
        fam = self.family
        if not isinstance(fam, Family):  # a bare _core.Family: as a picklable Family
            fam = (Family(fam.name) if fam.builtin else
                   Family(fam.name, list(fam.codes), fam.bits, fam.hamming, fam.mirror,
                          fam.excluded))
        return (_detector_of_state, (type(self), fam, self.params, self.max_detections,
                                     dict(self._geometry)))

    def __repr__(self):
        return "Detector(family={!r}, tag_size={:g})".format(self.family.name,
                                                              self.params["tag_size"])


def _detector_of_state(cls, family, params, max_detections, geometry):
    """Detector.__reduce__'s inverse."""
    return cls(family, max_detections=max_detections, **geometry, **params)


def detect(frame, *, family=DEFAULT_FAMILY, max_detections=DEFAULT_MAX_DETECTIONS,
           tuning=None, **kwargs):
    """Detect AcTags in one sonar frame; returns a list of ``Detection``.

    ``pyactag.detect(frame, min_range=0.1, max_range=1.5, aperture_deg=60,
    family="AcTag24h10", tag_size=0.130628571)``

    Keywords: the sonar geometry (``min_range``, ``max_range`` in metres,
    ``aperture`` in radians or ``aperture_deg`` or ``bearings`` per column,
    ``range_ascending``, ``azimuth_ascending``) and any detection parameter
    of ``default_params()`` (C defaults when left out). Allocates a
    workspace for this call; a ``Detector`` keeps one between calls.
    """
    geometry = {k: kwargs.pop(k) for k in list(kwargs) if k in GEOMETRY_KEYS}
    det = Detector(family, max_detections=max_detections, tuning=tuning, **kwargs)
    return det.detect(frame, **geometry)
