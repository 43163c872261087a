#!/usr/bin/env python3
"""actag_rosbag: find AcTags in the sonar images of a ROS 2 bag.

    python3 actag_rosbag.py BAG [--topic NAME ...] [options]

Reads a ROS 2 bag (sqlite3 or MCAP) with the ``rosbags`` package (pip
install rosbags; no ROS installation needed) and writes one JSON line per
sonar message: topic, message type, the bag's log time and the header stamp
(nanoseconds), frame_id, rows, cols and the detections (pyactag's
``Detection.to_dict()``: the keys of ``actag_detect --json``, id, hamming,
decision_margin, mirrored, and inlier_ratio, which the tool does not print;
corners as [{"x_col", "y_row",
"range_m", "azimuth_rad"} x 4] in tag order TL, TR, BR, BL; x_col is the
column (beam), y_row the row (range bin) of the frame as stored in the message),
or an "error" key when a message cannot be used.

--pose adds each detection's 6-DOF pose in the sonar frame ("pose": pyactag's
``Pose.to_dict()``, the keys of ``actag_detect --pose``; --vertical-aperture-deg,
and --plane NX,NY,NZ,D with --plane-sd / --plane-tilt-deg when the vehicle knows
the plane the tags lie on). --track follows the tags of each topic across its
messages (one pyactag.Tracker per topic, messages in log-time order) and writes
the confirmed tracks instead of the detections: "tracks" (``Track.to_dict()``:
track, id, mirrored, measured, hits, missed, decision_margin, corners, ..., and
"pose" with --pose), "whole_frame" and "pixels".

Topics (all supported ones unless --topic is given):
  marine_acoustic_msgs/msg/ProjectedSonarImage
      geometry from the message: rows are its ``ranges`` (metres; increasing
      or decreasing, assumed evenly spaced: a warning is printed when they are
      not), columns its ``beam_directions`` with azimuth = atan2(-y, z) (the
      message's rotation about X; zero along Z), pixels image.data in range-major
      order (beam index fastest), dtype uint8 or uint16.
  sensor_msgs/msg/Image
      mono8 / 8UC1 / mono16 / 16UC1 frames with rows = range bins and columns =
      beams; the geometry comes from --min-range, --max-range and
      --aperture-deg or --bearings (and the orientation flags).

Exit status: 0 when every message was processed, 2 when an option was bad,
the bag could not be opened or read (an error on stderr; the lines written
before it stay), or any message failed (its "error" line; the others are
still processed).
"""

import argparse
import json
import math
import sqlite3
import struct
import sys
from pathlib import Path

try:
    import numpy as np
    from rosbags.highlevel import AnyReader, AnyReaderError
    from rosbags.rosbag2 import ReaderError
    from rosbags.serde import SerdeError
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore
except ImportError as e:  # pragma: no cover
    sys.stderr.write("actag_rosbag: needs numpy and rosbags (pip install rosbags): {}\n".format(e))
    sys.exit(2)

import pyactag

PROG = "actag_rosbag"
IMAGE = "sensor_msgs/msg/Image"
PROJECTED = "marine_acoustic_msgs/msg/ProjectedSonarImage"

# marine_acoustic_msgs (github.com/apl-ocean-engineering/marine_msgs), the
# fields this tool reads and writes; used when a bag carries no definitions.
MARINE_ACOUSTIC_MSGS = {
    "marine_acoustic_msgs/msg/PingInfo": """
float32 frequency
float32 sound_speed
float32[] tx_beamwidths
float32[] rx_beamwidths
""",
    "marine_acoustic_msgs/msg/SonarImageData": """
uint32 DTYPE_UINT8=0
uint32 DTYPE_INT8=1
uint32 DTYPE_UINT16=2
uint32 DTYPE_INT16=3
uint32 DTYPE_UINT32=4
uint32 DTYPE_INT32=5
uint32 DTYPE_UINT64=6
uint32 DTYPE_INT64=7
uint32 DTYPE_FLOAT32=8
uint32 DTYPE_FLOAT64=9
bool is_bigendian
uint32 dtype
uint32 beam_count
uint8[] data
""",
    PROJECTED: """
std_msgs/Header header
marine_acoustic_msgs/PingInfo ping_info
geometry_msgs/Vector3[] beam_directions
float32[] ranges
marine_acoustic_msgs/SonarImageData image
""",
}

DTYPE_UINT8, DTYPE_UINT16 = 0, 2


def typestore():
    """ROS 2 standard messages plus marine_acoustic_msgs."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = {}
    for name, text in MARINE_ACOUSTIC_MSGS.items():
        types.update(get_types_from_msg(text, name))
    store.register(types)
    return store


class MessageError(Exception):
    pass


# What a bag that cannot be opened or read raises: AnyReader wraps its
# readers' errors in AnyReaderError; a database or file that breaks while
# being read may also surface as the reader's own error or the OS's.
BAG_ERRORS = (AnyReaderError, ReaderError, sqlite3.Error, OSError)

# What reader.deserialize() raises for a message whose bytes do not hold its
# type (truncated, corrupt): AnyReaderError in recent rosbags, SerdeError or
# the decoder's own error in older ones.
DESERIALIZE_ERRORS = (AnyReaderError, SerdeError, struct.error, IndexError, ValueError,
                      TypeError)


def azimuths_of(beam_directions):
    """Azimuth (rad) of each beam: rotation about X, zero along Z."""
    return [math.atan2(-float(v.y), float(v.z)) for v in beam_directions]


def projected_frame(msg, warned, topic):
    """(frame, geometry dict) of a ProjectedSonarImage."""
    img = msg.image
    cols = int(img.beam_count)
    ranges = [float(r) for r in msg.ranges]
    rows = len(ranges)
    if cols < 1 or rows < 1:
        raise MessageError("empty image ({} ranges, beam_count {})".format(rows, cols))
    if len(msg.beam_directions) != cols:
        raise MessageError("{} beam_directions for beam_count {}".format(
            len(msg.beam_directions), cols))
    if img.dtype == DTYPE_UINT8:
        dtype = np.uint8
    elif img.dtype == DTYPE_UINT16:
        dtype = np.dtype(">u2" if img.is_bigendian else "<u2")
    else:
        raise MessageError("image dtype {} is not supported (uint8 or uint16 only)".format(
            img.dtype))
    data = np.asarray(img.data, dtype=np.uint8)
    need = rows * cols * np.dtype(dtype).itemsize
    if data.size != need:
        raise MessageError("image has {} bytes, {} ranges x {} beams need {}".format(
            data.size, rows, cols, need))
    frame = data.view(dtype).reshape(rows, cols)
    ascending = rows > 1 and ranges[-1] > ranges[0]
    lo, hi = min(ranges), max(ranges)
    if rows > 1:
        step = (hi - lo) / (rows - 1)
        expect = [ranges[0] + i * (ranges[-1] - ranges[0]) / (rows - 1) for i in range(rows)]
        worst = max(abs(a - b) for a, b in zip(ranges, expect))
        if step > 0 and worst > 0.01 * step and topic not in warned:
            warned.add(topic)
            sys.stderr.write("{}: {}: ranges are not evenly spaced (off by up to {:.3g} bins); "
                             "libactag maps rows linearly\n".format(PROG, topic, worst / step))
    geometry = dict(min_range=lo, max_range=hi, bearings=azimuths_of(msg.beam_directions),
                    range_ascending=ascending)
    return frame, geometry


def image_frame(msg):
    enc = msg.encoding.lower()
    if enc in ("mono8", "8uc1"):
        dtype, item = np.uint8, 1
    elif enc in ("mono16", "16uc1"):
        dtype, item = np.dtype(">u2" if msg.is_bigendian else "<u2"), 2
    else:
        raise MessageError("encoding '{}' is not supported (mono8, 8UC1, mono16, 16UC1)".format(
            msg.encoding))
    rows, cols, step = int(msg.height), int(msg.width), int(msg.step)
    if rows < 1 or cols < 1 or step < cols * item:
        raise MessageError("bad image size {} x {}, step {}".format(cols, rows, step))
    data = np.asarray(msg.data, dtype=np.uint8)
    if data.size < (rows - 1) * step + cols * item:
        raise MessageError("image data is {} bytes, {} x {} with step {} need more".format(
            data.size, cols, rows, step))
    if data.size < rows * step:  # the last row's padding may be missing
        data = np.concatenate([data, np.zeros(rows * step - data.size, np.uint8)])
    # Rows step bytes apart: a row-strided view, no copy.
    return data[: rows * step].reshape(rows, step)[:, : cols * item].view(dtype)


def stamp_ns(header):
    return int(header.stamp.sec) * 1000000000 + int(header.stamp.nanosec)


def parse_value(text):
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    if text.lower() == "none":
        return None
    return text


def build_parser():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n", 2)[2],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("bag", help="ROS 2 bag directory (sqlite3 or MCAP)")
    p.add_argument("--topic", action="append", default=[],
                   help="topic to read (repeatable; default: every supported topic)")
    p.add_argument("--family", default="AcTag24h10", help="tag family (default AcTag24h10)")
    p.add_argument("--tag-size", type=float, default=None,
                   help="side of the inner white square, metres (default 0.130628571)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="any pyactag parameter, e.g. --param max_bit_corrections=2")
    g = p.add_argument_group("geometry of sensor_msgs/Image topics")
    g.add_argument("--min-range", type=float, help="range of the nearest row, metres")
    g.add_argument("--max-range", type=float, help="range of the farthest row, metres")
    g.add_argument("--aperture-deg", type=float, help="horizontal aperture, degrees")
    g.add_argument("--bearings", help="file of one azimuth per column, radians")
    g.add_argument("--range-ascending", action="store_true",
                   help="row 0 is the nearest range (default: the farthest)")
    g.add_argument("--azimuth-ascending", action="store_true",
                   help="column 0 is the most negative bearing (default: +aperture/2; "
                   "not with --bearings)")
    g = p.add_argument_group("pose and tracking")
    g.add_argument("--pose", action="store_true",
                   help="each detection's (or track's) 6-DOF pose in the sonar frame")
    g.add_argument("--vertical-aperture-deg", type=float, default=None,
                   help="the sonar's vertical aperture for --pose, degrees (default 12)")
    g.add_argument("--plane", metavar="NX,NY,NZ,D", default=None,
                   help="for --pose: the plane n . p = d (sonar frame, metres) the tags lie on")
    g.add_argument("--plane-sd", type=float, default=0.0,
                   help="for --plane: sd of its offset, metres")
    g.add_argument("--plane-tilt-deg", type=float, default=0.0,
                   help="for --plane: sd of its tilt, degrees")
    g.add_argument("--track", action="store_true",
                   help="follow the tags of each topic across its messages (pyactag.Tracker) "
                   "and write the confirmed tracks")
    p.add_argument("--out", help="write the JSON lines here (default: stdout)")
    p.add_argument("--version", action="version",
                   version="%(prog)s (pyactag {})".format(pyactag.__version__))
    return p


def image_geometry(args):
    """Geometry for Image topics, or None when not given."""
    if args.min_range is None and args.max_range is None and args.aperture_deg is None and \
            args.bearings is None:
        return None
    if args.min_range is None or args.max_range is None:
        raise SystemExit("{}: --min-range and --max-range are both required for "
                         "sensor_msgs/Image topics".format(PROG))
    if (args.aperture_deg is None) == (args.bearings is None):
        raise SystemExit("{}: give --aperture-deg or --bearings (not both)".format(PROG))
    if args.bearings is not None and args.azimuth_ascending:
        raise SystemExit("{}: --azimuth-ascending does not apply with --bearings (the table "
                         "gives each column's azimuth in column order)".format(PROG))
    g = dict(min_range=args.min_range, max_range=args.max_range,
             range_ascending=args.range_ascending, azimuth_ascending=args.azimuth_ascending)
    if args.bearings is not None:
        with open(args.bearings) as f:
            g["bearings"] = [float(t) for t in f.read().split()]
    else:
        g["aperture_deg"] = args.aperture_deg
    return g


def pose_options(args):
    """sonar_pose's keywords from the options (checked: a bad value is a
    SystemExit naming it), or None without --pose."""
    given = [o for o, v in (("--vertical-aperture-deg", args.vertical_aperture_deg),
                            ("--plane", args.plane), ("--plane-sd", args.plane_sd or None),
                            ("--plane-tilt-deg", args.plane_tilt_deg or None)) if v is not None]
    if not args.pose:
        if given:
            raise SystemExit("{}: {} needs --pose".format(PROG, given[0]))
        return None
    kw = dict(vertical_aperture_deg=12.0 if args.vertical_aperture_deg is None
              else args.vertical_aperture_deg, plane_sd=args.plane_sd,
              plane_tilt_deg=args.plane_tilt_deg)
    if args.plane is not None:
        try:
            kw["plane"] = [float(t) for t in args.plane.split(",")]
        except ValueError:
            raise SystemExit("{}: --plane expects NX,NY,NZ,D (numbers), not '{}'".format(
                PROG, args.plane)) from None
    # every value checked now, on made-up corners, rather than at the first tag
    try:
        pyactag.sonar_pose([(1.0, 0.05), (1.05, -0.05), (1.0, -0.1), (0.95, 0.0)], False,
                           tag_size=0.1, **kw)
    except (TypeError, ValueError) as e:
        raise SystemExit("{}: {}".format(PROG, e)) from None
    return kw


def main(argv=None):
    args = build_parser().parse_args(argv)
    params = {}
    for item in args.param:
        if "=" not in item:
            sys.stderr.write("{}: --param expects NAME=VALUE, not '{}'\n".format(PROG, item))
            return 2
        k, v = item.split("=", 1)
        params[k.strip()] = parse_value(v.strip())
    if args.tag_size is not None:
        params["tag_size"] = args.tag_size
    try:
        img_geo = image_geometry(args)
        detector = pyactag.Detector(args.family, **params)
        args.pose_kw = pose_options(args)
    except SystemExit as e:
        sys.stderr.write(str(e) + "\n")
        return 2
    except (TypeError, ValueError, OverflowError, OSError) as e:
        sys.stderr.write("{}: {}\n".format(PROG, e))
        return 2

    try:
        out = open(args.out, "w") if args.out else sys.stdout
    except OSError as e:
        sys.stderr.write("{}: {}\n".format(PROG, e))
        return 2
    try:
        return process_bag(args, detector, img_geo, out)
    except BAG_ERRORS as e:
        sys.stderr.write("{}: {}: cannot read the bag: {}\n".format(PROG, args.bag, e))
        return 2
    finally:
        if out is not sys.stdout:
            out.close()


def with_pose(record, source, item, args):
    """record with "pose" (None when the library refuses the corners) under
    --pose; source: the Detector or Tracker that found item."""
    if args.pose_kw is not None:
        try:
            record["pose"] = source.pose(item, **args.pose_kw).to_dict()
        except pyactag.ActagError:
            record["pose"] = None
    return record


def process_bag(args, detector, img_geo, out):
    """One JSON line per message of the chosen topics; the exit status."""
    status, warned, trackers = 0, set(), {}
    with AnyReader([Path(args.bag)], default_typestore=typestore()) as reader:
        conns = [c for c in reader.connections if c.msgtype in (IMAGE, PROJECTED)]
        if args.topic:
            missing = set(args.topic) - {c.topic for c in reader.connections}
            if missing:
                sys.stderr.write("{}: {}: no topic {}\n".format(PROG, args.bag,
                                                                 ", ".join(sorted(missing))))
                return 2
            conns = [c for c in conns if c.topic in args.topic]
            unsupported = set(args.topic) - {c.topic for c in conns}
            if unsupported:
                sys.stderr.write("{}: topics {} are not Image or ProjectedSonarImage\n".format(
                    PROG, ", ".join(sorted(unsupported))))
                return 2
        if not conns:
            sys.stderr.write("{}: {}: no sensor_msgs/Image or ProjectedSonarImage topic\n"
                             .format(PROG, args.bag))
            return 2
        if img_geo is None and any(c.msgtype == IMAGE for c in conns):
            sys.stderr.write("{}: sensor_msgs/Image topics need --min-range, --max-range "
                             "and --aperture-deg or --bearings\n".format(PROG))
            return 2
        for conn, log_time, raw in reader.messages(connections=conns):
            line = {"topic": conn.topic, "type": conn.msgtype, "log_time_ns": int(log_time)}
            try:
                try:
                    msg = reader.deserialize(raw, conn.msgtype)
                except DESERIALIZE_ERRORS as e:
                    raise MessageError("cannot deserialize the message ({} bytes): {}".format(
                        len(raw), e)) from e
                line["stamp_ns"] = stamp_ns(msg.header)
                line["frame_id"] = msg.header.frame_id
                if conn.msgtype == PROJECTED:
                    frame, geo = projected_frame(msg, warned, conn.topic)
                else:
                    frame, geo = image_frame(msg), img_geo
                line["rows"], line["cols"] = int(frame.shape[0]), int(frame.shape[1])
                if args.track:
                    tr = trackers.get(conn.topic)
                    if tr is None:  # one stream per topic, the detector's settings
                        tr = trackers[conn.topic] = pyactag.Tracker(detector.family,
                                                                    **detector.params)
                    tracks = tr.update(frame, **geo)
                    line["tracks"] = [with_pose(t.to_dict(), tr, t, args) for t in tracks]
                    line["whole_frame"] = tr.stats["full_frame"]
                    line["pixels"] = tr.stats["pixels"]
                else:
                    dets = detector.detect(frame, **geo)
                    line["detections"] = [with_pose(d.to_dict(), detector, d, args)
                                          for d in dets]
            except (MessageError, pyactag.ActagError, ValueError, TypeError) as e:
                line["error"] = str(e)
                sys.stderr.write("{}: {} at {}: {}\n".format(PROG, conn.topic, log_time, e))
                status = 2
            out.write(json.dumps(line) + "\n")
    return status


if __name__ == "__main__":
    sys.exit(main())
