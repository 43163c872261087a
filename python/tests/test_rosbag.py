"""examples/actag_rosbag.py: bags written from the pool frames with rosbags
(sqlite3 and MCAP, sensor_msgs/Image and ProjectedSonarImage topics) and
read back by the tool; its JSON lines equal direct pyactag calls."""
import contextlib
import functools
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

import pyactag
from conftest import GEOMETRY, pool_paths

np = pytest.importorskip("numpy")
pytest.importorskip("rosbags")
from rosbags.rosbag2 import StoragePlugin, Writer  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TOOL = EXAMPLES / "actag_rosbag.py"
sys.path.insert(0, str(EXAMPLES))
import actag_rosbag  # noqa: E402

APERTURE = math.radians(60.0)
NFRAMES = 8


@pytest.fixture(scope="module")
def frames(example_frame):
    paths = pool_paths()
    if not paths:  # still a bag: the example frame, cropped to the pool's size, and a blank one
        f = np.ascontiguousarray(example_frame[:, 50:562])
        return [f, np.ascontiguousarray(f[:, ::-1]), np.zeros_like(f)]
    # Frames with and without the tag: every 5th of the 58 (or the subset).
    if len(paths) > NFRAMES:
        paths = paths[::5][:NFRAMES]
    return [pyactag.read_pgm(p) for p in paths]


def beam_directions(store, cols):
    """Unit vectors of the beams, column 0 = +30 degrees: azimuth = atan2(-y, z)."""
    V = store.types["geometry_msgs/msg/Vector3"]
    az = [APERTURE / 2 - i * APERTURE / (cols - 1) for i in range(cols)]
    return [V(x=0.0, y=-math.sin(a), z=math.cos(a)) for a in az]


def header(store, i, frame_id="sonar"):
    H, T = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    return H(stamp=T(sec=1700000000 + i, nanosec=1000 * i + 7), frame_id=frame_id)


def image_msg(store, i, frame, encoding="mono8", pad=0):
    Image = store.types["sensor_msgs/msg/Image"]
    rows, cols = frame.shape
    item = frame.dtype.itemsize
    step = cols * item + pad
    data = np.zeros((rows, step), np.uint8)
    data[:, :cols * item] = frame.view(np.uint8).reshape(rows, cols * item)
    return Image(header=header(store, i), height=rows, width=cols, encoding=encoding,
                 is_bigendian=0, step=step, data=data.ravel())


def projected_msg(store, i, frame, dirs):
    """Rows stored nearest range first (ranges increasing), as sonar drivers do."""
    T = store.types
    rows, cols = frame.shape
    stored = np.ascontiguousarray(frame[::-1])
    ranges = np.array([0.1 + r * 1.4 / (rows - 1) for r in range(rows)], np.float32)
    dtype = 0 if frame.dtype == np.uint8 else 2
    data = stored.astype("<u2").view(np.uint8) if dtype == 2 else stored
    img = T["marine_acoustic_msgs/msg/SonarImageData"](is_bigendian=False, dtype=dtype,
                                                      beam_count=cols, data=data.ravel())
    ping = T["marine_acoustic_msgs/msg/PingInfo"](
        frequency=1.2e6, sound_speed=1500.0, tx_beamwidths=np.zeros(0, np.float32),
        rx_beamwidths=np.zeros(0, np.float32))
    return T["marine_acoustic_msgs/msg/ProjectedSonarImage"](
        header=header(store, i), ping_info=ping, beam_directions=dirs, ranges=ranges, image=img)


def write_bag(path, storage, frames):
    store = store_for_tests()
    dirs = beam_directions(store, frames[0].shape[1])
    written = []
    with Writer(path, version=9, storage_plugin=storage) as w:
        ci = w.add_connection("/sonar/image", actag_rosbag.IMAGE, typestore=store)
        cp = w.add_connection("/sonar/projected", actag_rosbag.PROJECTED, typestore=store)
        cb = w.add_connection("/sonar/colour", actag_rosbag.IMAGE, typestore=store)
        for i, f in enumerate(frames):
            t = 1700000000 * 10 ** 9 + i * 10 ** 8
            msg = image_msg(store, i, f, pad=3 if i % 2 else 0)
            w.write(ci, t, store.serialize_cdr(msg, actag_rosbag.IMAGE))
            msg = projected_msg(store, i, f, dirs)
            w.write(cp, t + 1, store.serialize_cdr(msg, actag_rosbag.PROJECTED))
            written.append(("/sonar/image", t, i))
            written.append(("/sonar/projected", t + 1, i))
        bad = image_msg(store, 99, frames[0])
        bad.encoding = "rgb8"
        w.write(cb, 1700000000 * 10 ** 9 + 10 ** 10, store.serialize_cdr(bad, actag_rosbag.IMAGE))
    return written


def run_tool(*args, subprocess_run=False):
    """(exit status, JSON lines, stderr) of the tool; in this process unless
    subprocess_run (the script as a program)."""
    argv = [str(a) for a in args]
    if subprocess_run:
        p = subprocess.run([sys.executable, str(TOOL)] + argv, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, universal_newlines=True)
        rc, out, err = p.returncode, p.stdout, p.stderr
    else:
        o, e = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(o), contextlib.redirect_stderr(e):
            rc = actag_rosbag.main(argv)
        out, err = o.getvalue(), e.getvalue()
    return rc, [json.loads(x) for x in out.splitlines()], err


@functools.lru_cache(maxsize=None)
def store_for_tests():
    return actag_rosbag.typestore()


def expected_projected(frame):
    """What the tool must compute: the message's stored frame and geometry
    (ranges travel as float32)."""
    dirs = beam_directions(store_for_tests(), frame.shape[1])
    bearings = [math.atan2(-v.y, v.z) for v in dirs]  # Vector3 is float64
    ranges = np.array([0.1 + r * 1.4 / (frame.shape[0] - 1) for r in range(frame.shape[0])],
                      np.float32)
    return pyactag.detect(np.ascontiguousarray(frame[::-1]), min_range=float(ranges.min()),
                          max_range=float(ranges.max()), bearings=bearings, range_ascending=True)


@pytest.mark.parametrize("storage", [StoragePlugin.SQLITE3, StoragePlugin.MCAP],
                         ids=["sqlite3", "mcap"])
def test_bag_round_trip(tmp_path, frames, storage):
    bag = tmp_path / "bag"
    written = write_bag(bag, storage, frames)
    rc, lines, err = run_tool(bag, "--topic", "/sonar/image", "--topic", "/sonar/projected",
                              "--min-range", 0.1, "--max-range", 1.5, "--aperture-deg", 60,
                              subprocess_run=storage == StoragePlugin.SQLITE3)
    assert rc == 0, err
    assert [(x["topic"], x["log_time_ns"]) for x in lines] == [(t, n) for t, n, _ in written]
    tagged = agree = 0
    for line, (topic, _, i) in zip(lines, written):
        f = frames[i]
        assert line["stamp_ns"] == (1700000000 + i) * 10 ** 9 + 1000 * i + 7
        assert line["frame_id"] == "sonar" and (line["rows"], line["cols"]) == f.shape
        if topic == "/sonar/image":
            want = pyactag.detect(f, **GEOMETRY)
        else:
            want = expected_projected(f)
            plain = pyactag.detect(f, **GEOMETRY)
            # Same tag in the same place as the default orientation sees it.
            if plain and want:
                tagged += 1
                if plain[0].id == want[0].id:
                    agree += 1
                    for (r1, a1), (r2, a2) in zip(plain[0].corners_polar,
                                                  want[0].corners_polar):
                        assert abs(r1 - r2) < 0.03 and abs(a1 - a2) < 0.03
        assert line["detections"] == json.loads(json.dumps([d.to_dict() for d in want])), (
            topic, i)
    assert tagged >= 1 and agree == tagged
    # All topics: the rgb8 image is reported, the rest still processed, status 2.
    rc, lines, err = run_tool(bag, "--min-range", 0.1, "--max-range", 1.5, "--aperture-deg", 60)
    assert rc == 2 and "rgb8" in err
    assert len(lines) == 2 * len(frames) + 1
    assert [x for x in lines if "error" in x][0]["topic"] == "/sonar/colour"


def test_sixteen_bit_projected(tmp_path, frames):
    bag = tmp_path / "bag16"
    store = store_for_tests()
    f16 = frames[0].astype(np.uint16) * 250
    with Writer(bag, version=9) as w:
        c = w.add_connection("/p", actag_rosbag.PROJECTED, typestore=store)
        msg = projected_msg(store, 0, f16, beam_directions(store, f16.shape[1]))
        w.write(c, 5, store.serialize_cdr(msg, actag_rosbag.PROJECTED))
    rc, lines, err = run_tool(bag)
    assert rc == 0, err
    want = expected_projected(f16)
    assert lines[0]["detections"] == json.loads(json.dumps([d.to_dict() for d in want]))


def test_tool_errors(tmp_path, frames):
    bag = tmp_path / "bag"
    write_bag(bag, StoragePlugin.SQLITE3, frames[:1])
    rc, _, err = run_tool(bag, "--topic", "/sonar/image")
    assert rc == 2 and "--min-range" in err  # Image topics need the geometry
    rc, _, err = run_tool(bag, "--topic", "/nope")
    assert rc == 2 and "no topic /nope" in err
    rc, _, err = run_tool(bag, "--param", "median_radius=-1")
    assert rc == 2 and "ACTAG_ERR_PARAM" in err
    rc, _, err = run_tool(bag, "--min-range", 0.1, "--max-range", 1.5)
    assert rc == 2 and "--aperture-deg" in err
    rc, lines, _ = run_tool(bag, "--topic", "/sonar/projected", "--param",
                            "max_bit_corrections=0")
    assert rc == 0 and len(lines) == 1


def test_undeserializable_message_reported_and_skipped(tmp_path, frames):
    # A truncated message (its bytes end inside the header, or inside the
    # image) between valid ones: an "error" line each, the others processed,
    # exit status 2 (README, the tool's docstring).
    bag = tmp_path / "truncated"
    store = store_for_tests()
    dirs = beam_directions(store, frames[0].shape[1])
    raw = bytes(store.serialize_cdr(projected_msg(store, 0, frames[0], dirs),
                                    actag_rosbag.PROJECTED))
    with Writer(bag, version=9) as w:
        c = w.add_connection("/p", actag_rosbag.PROJECTED, typestore=store)
        w.write(c, 1, raw[:200])
        w.write(c, 2, raw)
        w.write(c, 3, raw[:len(raw) // 2])
        w.write(c, 4, raw)
    rc, lines, err = run_tool(bag, subprocess_run=True)
    assert rc == 2, err
    assert "Traceback" not in err
    assert [x["log_time_ns"] for x in lines] == [1, 2, 3, 4]
    want = json.loads(json.dumps([d.to_dict() for d in expected_projected(frames[0])]))
    for bad in (lines[0], lines[2]):
        assert "cannot deserialize" in bad["error"] and "detections" not in bad
        assert "/p at {}: cannot deserialize".format(bad["log_time_ns"]) in err
    for good in (lines[1], lines[3]):
        assert "error" not in good and good["detections"] == want


def test_unusable_bag(tmp_path, frames):
    # A bag that cannot be opened or read: a message naming it, exit status 2.
    rc, lines, err = run_tool(tmp_path / "missing", subprocess_run=True)
    assert rc == 2 and lines == [] and "Traceback" not in err
    assert "missing: cannot read the bag" in err
    empty = tmp_path / "empty"
    empty.mkdir()
    rc, lines, err = run_tool(empty)
    assert rc == 2 and lines == [] and "empty: cannot read the bag" in err
    bag = tmp_path / "bag"
    write_bag(bag, StoragePlugin.SQLITE3, frames[:1])
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: [\n")
    rc, lines, err = run_tool(bag)
    assert rc == 2 and lines == [] and "bag: cannot read the bag" in err
    bag = tmp_path / "cut"
    write_bag(bag, StoragePlugin.SQLITE3, frames[:1])
    db = next(bag.glob("*.db3"))
    db.write_bytes(db.read_bytes()[:3000])
    rc, lines, err = run_tool(bag)
    assert rc == 2 and lines == [] and "cut: cannot read the bag" in err


def test_azimuth_ascending_refused_with_bearings(tmp_path, frames):
    bag = tmp_path / "bag"
    write_bag(bag, StoragePlugin.SQLITE3, frames[:1])
    table = tmp_path / "bearings.txt"
    cols = frames[0].shape[1]
    table.write_text("\n".join(str(APERTURE / 2 - i * APERTURE / (cols - 1))
                               for i in range(cols)))
    rc, lines, err = run_tool(bag, "--topic", "/sonar/image", "--min-range", 0.1,
                              "--max-range", 1.5, "--bearings", table, "--azimuth-ascending")
    assert rc == 2 and lines == []
    assert "--azimuth-ascending does not apply with --bearings" in err
    rc, lines, err = run_tool(bag, "--topic", "/sonar/image", "--min-range", 0.1,
                              "--max-range", 1.5, "--bearings", table)
    assert rc == 0 and len(lines) == 1 and "error" not in lines[0], err


def test_pose_and_track(tmp_path, frames):
    # --pose: each detection's pose is Detector.pose's; --track: each topic is
    # one stream through its own Tracker, tracks and poses as direct calls.
    bag = tmp_path / "bag"
    write_bag(bag, StoragePlugin.SQLITE3, frames)
    geo = ("--min-range", 0.1, "--max-range", 1.5, "--aperture-deg", 60)
    rc, lines, err = run_tool(bag, "--topic", "/sonar/image", "--pose",
                              "--vertical-aperture-deg", 20, *geo)
    assert rc == 0, err
    det = pyactag.Detector("AcTag24h10", **GEOMETRY)
    posed = 0
    for line, f in zip(lines, frames):
        want = [dict(d.to_dict(), pose=det.pose(d, vertical_aperture_deg=20).to_dict())
                for d in det.detect(f)]
        assert line["detections"] == json.loads(json.dumps(want))
        posed += len(want)
    assert posed >= 1
    rc, lines, err = run_tool(bag, "--topic", "/sonar/image", "--topic", "/sonar/projected",
                              "--track", "--pose", "--plane", "0,0,1,-0.5", "--plane-sd", 0.05,
                              *geo)
    assert rc == 0, err
    image = [x for x in lines if x["topic"] == "/sonar/image"]
    assert len(image) == len(frames) and all("detections" not in x for x in lines)
    tr = pyactag.Tracker("AcTag24h10", **GEOMETRY)
    tracked = 0
    for line, f in zip(image, frames):
        tracks = tr.update(f)
        want = [dict(t.to_dict(), pose=tr.pose(t, plane=(0, 0, 1, -0.5), plane_sd=0.05).to_dict())
                for t in tracks]
        assert line["tracks"] == json.loads(json.dumps(want))
        assert line["whole_frame"] == tr.stats["full_frame"]
        assert line["pixels"] == tr.stats["pixels"]
        tracked += len(want)
    assert tracked >= 1
    # the projected topic is a stream of its own: its first message searched whole
    assert [x for x in lines if x["topic"] == "/sonar/projected"][0]["whole_frame"]


@pytest.mark.parametrize("args,words", [
    (("--plane-sd", 0.1), "needs --pose"),
    (("--vertical-aperture-deg", 12), "needs --pose"),
    (("--pose", "--plane", "0,0,x,1", "--plane-sd", 0.1), "--plane expects"),
    (("--pose", "--vertical-aperture-deg", 200), "vertical_aperture_deg"),
    (("--pose", "--plane", "0,0,1,-1"), "plane_sd"),
    (("--pose", "--plane-sd", 0.1), "need plane"),
])
def test_pose_option_errors(tmp_path, frames, args, words):
    bag = tmp_path / "bag"
    write_bag(bag, StoragePlugin.SQLITE3, frames[:1])
    rc, lines, err = run_tool(bag, "--topic", "/sonar/projected", *args)
    assert rc == 2 and lines == [] and words in err, err
