"""Threads: results independent of concurrency, the GIL released while
libactag works."""
import sys
import threading
import time

import pytest

import pyactag
from conftest import GEOMETRY, detections_key

np = pytest.importorskip("numpy")


def frames_for_threads(example_frame):
    from conftest import pool_paths
    paths = pool_paths()[:8]
    frames = [pyactag.read_pgm(p) for p in paths]
    return frames + [example_frame, example_frame[:, ::-1], example_frame[::2]]


def test_shared_and_private_detectors_in_threads(example_frame):
    frames = frames_for_threads(example_frame)
    shared = pyactag.Detector(**GEOMETRY)
    expected = [detections_key(shared.detect(f)) for f in frames]
    errors, results = [], {}

    def worker(t):
        try:
            own = pyactag.Detector(**GEOMETRY)
            out = []
            for rep in range(1):
                for i, f in enumerate(frames):
                    det = shared if (i + t + rep) % 2 else own
                    out.append((i, detections_key(det.detect(f))))
            results[t] = out
        except Exception as e:  # pragma: no cover - reported below
            errors.append(repr(e))

    threads = [threading.Thread(target=worker, args=(t,)) for t in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert not errors, errors
    assert len(results) == 4
    for out in results.values():
        for i, key in out:
            assert key == expected[i]


def test_gil_released_during_detection(example_frame):
    """With the interpreter's forced switching turned off, another Python
    thread can only run during a call if the call released the GIL."""
    big = np.tile(example_frame, (3, 3))  # ~9x the work of one frame
    det = pyactag.Detector(**GEOMETRY)
    det.detect(big)  # allocate the workspace first
    counter = [0]
    stop = threading.Event()

    def spinner():
        while not stop.is_set():
            counter[0] += 1
            time.sleep(0.0002)  # also releases the GIL between increments

    old = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    th = threading.Thread(target=spinner)
    th.start()
    progressed = []
    try:
        time.sleep(0.01)
        for _ in range(10):
            before = counter[0]
            det.detect(big)
            progressed.append(counter[0] - before)
            if progressed[-1] > 0:
                break
    finally:
        stop.set()
        th.join()
        sys.setswitchinterval(old)
    assert max(progressed) > 0, "no other thread ran during detect(): GIL held"
