"""pyactag: AcTag detection in imaging-sonar frames, by libactag.

    import pyactag
    frame = pyactag.read_pgm("data/exampleSonarImage.pgm")   # or any 2-D uint8/uint16 array
    for d in pyactag.detect(frame, min_range=0.1, max_range=1.5, aperture_deg=60):
        print(d.id, d.hamming, d.decision_margin, d.mirrored, d.corners_xy, d.corners_polar)

Coordinates: corners_xy are (x = column, y = row) pixels; corners_polar
(range m, azimuth rad). Users of the reference package switch with
``from pyactag import AcTag`` (see pyactag.compat).
"""

from . import _core
from ._arrays import have_numpy
from ._core import ActagError
from .compat import AcTag
from .detection import (GEOMETRY_KEYS, Corner, Detection, Detector, Result, default_params, detect,
                        tuning_names)
from .families import Family, code_mirror, code_reverse, code_rot90, family_names, rule_of_name
from .pgm import parse_pgm, read_pgm, write_pgm
from .pose import (POSE_AZIMUTH_SD, POSE_FLAGS, POSE_PIXEL_SD_MAX, POSE_PIXEL_SD_MIN,
                   POSE_RANGE_SD, Pose, camera_pose, sonar_pose)
from .tracking import TRACK_PARAMS, Track, Tracker, TrackResult

__version__ = _core.LIBRARY_VERSION
LIBRARY_VERSION = _core.LIBRARY_VERSION

CORNER_TOP_LEFT = _core.CORNER_TOP_LEFT
CORNER_TOP_RIGHT = _core.CORNER_TOP_RIGHT
CORNER_BOTTOM_RIGHT = _core.CORNER_BOTTOM_RIGHT
CORNER_BOTTOM_LEFT = _core.CORNER_BOTTOM_LEFT


def workspace_size(rows, cols):
    """Bytes of workspace libactag needs for rows x cols frames (0 for bad
    sizes: any integer outside 1..``_core.MAX_DIM``; a non-integer is a
    TypeError)."""
    return _core.workspace_size(rows, cols)


def strerror(code):
    """The library's message for an ACTAG_* code."""
    return _core.strerror(code)


__all__ = [
    "AcTag", "ActagError", "Corner", "Detection", "Detector", "Family", "GEOMETRY_KEYS", "Pose",
    "Result", "camera_pose", "code_mirror", "code_reverse", "code_rot90", "default_params",
    "detect", "family_names", "have_numpy", "parse_pgm", "read_pgm", "rule_of_name",
    "sonar_pose", "strerror", "tuning_names", "workspace_size", "write_pgm", "LIBRARY_VERSION",
    "CORNER_TOP_LEFT", "CORNER_TOP_RIGHT", "CORNER_BOTTOM_RIGHT", "CORNER_BOTTOM_LEFT",
    "POSE_AZIMUTH_SD", "POSE_FLAGS", "POSE_PIXEL_SD_MAX", "POSE_PIXEL_SD_MIN", "POSE_RANGE_SD",
    "TRACK_PARAMS", "Track", "Tracker", "TrackResult",
]
