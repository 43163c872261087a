"""Following tags across the pings of one sonar stream (C: actag/track.h).

    tr = pyactag.Tracker("AcTag24h10", tag_size=0.130628571,
                         min_range=0.1, max_range=1.5, aperture_deg=60)
    for frame in frames:                      # in stream order
        for t in tr.update(frame):            # the confirmed tracks
            print(t.track_id, t.id, t.measured, t.corners_xy)

Each frame, the tracker first reads its confirmed tracks where they are
predicted, then searches regions around the tracks it could not read, and
the whole frame every ``full_every`` frames or when no track is confirmed.
A track never changes its tag ID or handedness; a new tag is confirmed after
``confirm_frames`` consistent frames (or one reading of ``confirm_margin``).
"""
from collections import namedtuple

from . import _core
from ._record import SlotRecord
from .detection import (DEFAULT_FAMILY, Corner, Detection, _family, _geometry, _Searcher,
                        _split_params, _stored_geometry)

#: The fields of ``track_params`` with their C defaults (actag_track_params_default).
TRACK_PARAMS = ("full_every", "confirm_frames", "confirm_margin", "max_missed", "roi_scale",
                "gate", "smoothing", "refind_after", "verify", "report_coasting")

#: ``Tracker.run``'s result: the confirmed tracks and the frame's counters.
TrackResult = namedtuple("TrackResult", ["tracks", "stats"])


class Track(SlotRecord):
    """A confirmed track as ``Tracker.update`` reports it (``actag_track``).

    Attributes:
        track_id: the track's number in its tracker (never 0, not reused).
        id: tag ID; mirrored: handedness (neither ever changes).
        confirmed: always True in what ``update`` returns.
        measured: True when read in this frame, False when coasting on the
            prediction (reported only with ``report_coasting``, on the first
            frame a track misses).
        hits: frames with a reading; missed: consecutive frames without one;
            age: frames since the track started.
        corners_xy: the smoothed corners (x = column, y = row), tag order
            (TL, TR, BR, BL); corners_polar: their (range m, azimuth rad).
        velocity_xy: each corner's velocity, pixels per frame.
        innovation: pixels between the latest reading's corners and the
            prediction (the largest of the four; 0 after the first reading).
            A reading more than a quarter of its diagonal from the prediction is
            reported as read, not smoothed.
        last: the latest reading, a ``Detection`` (unsmoothed).
    """

    __slots__ = ("track_id", "id", "mirrored", "confirmed", "measured", "hits", "missed", "age",
                 "corners_xy", "corners_polar", "velocity_xy", "innovation", "last")

    def __init__(self, track_id, id, mirrored, confirmed, measured, hits, missed, age,
                 corners_xy, corners_polar, velocity_xy, innovation, last):
        self.track_id = track_id
        self.id = id
        self.mirrored = mirrored
        self.confirmed = confirmed
        self.measured = measured
        self.hits = hits
        self.missed = missed
        self.age = age
        self.corners_xy = corners_xy
        self.corners_polar = corners_polar
        self.velocity_xy = velocity_xy
        self.innovation = innovation
        self.last = last

    @classmethod
    def _of_core(cls, t):
        return cls(*t[:12], Detection(*t[12]))

    @property
    def corners(self):
        """The smoothed corners as ``Corner(x_col, y_row, range_m, azimuth_rad)``."""
        return tuple(Corner(x, y, r, a) for (x, y), (r, a) in zip(self.corners_xy,
                                                                   self.corners_polar))

    @property
    def decision_margin(self):
        """The latest reading's decision margin."""
        return self.last.decision_margin

    def to_dict(self):
        """Plain dict (JSON-ready) with the keys ``actag_detect --track --json``
        prints per track (track, id, mirrored, measured, hits, missed,
        innovation, decision_margin, corners) and confirmed, age, velocity_xy."""
        return {
            "track": self.track_id,
            "id": self.id,
            "mirrored": self.mirrored,
            "measured": self.measured,
            "hits": self.hits,
            "missed": self.missed,
            "decision_margin": self.decision_margin,
            "corners": [c._asdict() for c in self.corners],
            "confirmed": self.confirmed,
            "age": self.age,
            "velocity_xy": [list(v) for v in self.velocity_xy],
            "innovation": self.innovation,
        }

    def __repr__(self):
        return "Track(track_id={}, id={}, mirrored={}, measured={}, hits={})".format(
            self.track_id, self.id, self.mirrored, self.measured, self.hits)


class Tracker(_Searcher):
    """Tags followed across the frames of one sonar stream (``actag_tracker``).

    ``Tracker(family="AcTag24h10", *, min_range, max_range, aperture |
    aperture_deg | bearings, range_ascending=False, azimuth_ascending=False,
    track_params=None, roi_params=None, tuning=None, **params)``

    - the geometry and ``params`` (``tag_size``, ``min_margin``, the tuning
      names...) are those of ``Detector``; geometry given here is the default
      of every ``update()``, which may override it (a new range setting
      mid-stream keeps the tracks: track.h);
    - ``track_params``: a dict of ``TRACK_PARAMS`` fields (``full_every``,
      ``confirm_frames``, ``confirm_margin``, ``max_missed``, ``roi_scale``,
      ``gate``, ``smoothing``, ``refind_after``, ``verify``,
      ``report_coasting``), the C defaults for the others (``track_params``
      property); ``report_coasting: 1`` also reports a track on the first
      frame it is not read, at its prediction (``measured`` False);
    - ``roi_params``: changes of ``params`` for the searches around tracks
      (e.g. ``{"min_margin": -2}``: only a track's own ID can update it
      there; not ``tag_size``: the tags are the tracked ones); None: the
      whole-frame parameters.

    Bad values raise TypeError, ValueError, OverflowError or ActagError
    naming them (``stats`` is None after a failed ``update()``). A
    Tracker follows one stream: ``update()`` releases the GIL, and a second
    ``update()`` of the same Tracker from another thread meanwhile is a
    RuntimeError. Same frames, same parameters: same tracks, on every
    platform (as ``actag_detect --track``).
    """

    def __init__(self, family=DEFAULT_FAMILY, *, track_params=None, roi_params=None, tuning=None,
                 min_range=None, max_range=None, aperture=None, aperture_deg=None, bearings=None,
                 range_ascending=False, azimuth_ascending=False, **params):
        if track_params is not None and not isinstance(track_params, dict):
            raise TypeError("track_params must be a dict of {} (or None), got {!r}".format(
                ", ".join(TRACK_PARAMS), track_params))
        if roi_params is not None and not isinstance(roi_params, dict):
            raise TypeError("roi_params must be a dict of parameters (or None), got {!r}".format(
                roi_params))
        self._core = _core.Tracker(_family(family), _split_params(params, tuning),
                                   None if roi_params is None else dict(roi_params),
                                   None if track_params is None else dict(track_params))
        self._geometry = _stored_geometry(min_range, max_range, aperture, aperture_deg, bearings,
                                          range_ascending, azimuth_ascending)
        self.stats = None

    @property
    def roi_params(self):
        """The parameters of the searches around tracks (a dict copy)."""
        return self._core.roi_params

    @property
    def track_params(self):
        """The tracker's settings (a dict copy, every ``TRACK_PARAMS`` field)."""
        return self._core.track_params

    @property
    def frames(self):
        """Frames fed so far (failed ones included)."""
        return self._core.frame

    def run(self, frame, **geometry):
        """Feed the next frame of the stream; returns ``TrackResult(tracks,
        stats)``: the confirmed tracks (list of ``Track``, in track order) and
        the frame's counters (``actag_track_stats``: full_frame, rois,
        pixels, readings, conflicts, started, confirmed, dropped, verified,
        quads, decoded, searched)."""
        self.stats = None  # until this frame's counters exist
        g = _geometry(self._geometry, geometry)
        raw, stats = self._core.update(frame, g["min_range"], g["max_range"], g["aperture"],
                                       g["bearings"], g["range_ascending"],
                                       g["azimuth_ascending"])
        self.stats = stats
        return TrackResult([Track._of_core(t) for t in raw], stats)

    def update(self, frame, **geometry):
        """Feed the next frame; returns the confirmed tracks (see ``run``);
        the frame's counters are then ``self.stats``."""
        return self.run(frame, **geometry).tracks

    def pose(self, track, **options):
        """The pose of a track's smoothed corners (``pyactag.sonar_pose`` with
        this tracker's family and tag_size; ``options`` its keywords)."""
        if not isinstance(track, Track):
            raise TypeError("pose() takes a Track, got {!r}".format(track))
        return self._pose(track.corners_polar, track.mirrored, options)

    def __repr__(self):
        return "Tracker(family={!r}, frames={})".format(self.family.name, self.frames)
