"""2-D pixel arrays without requiring numpy.

numpy is optional: with it, images come back as ``numpy.ndarray`` (uint8 or
uint16, shape (rows, cols)); without it (or with PYACTAG_NO_NUMPY=1 in the
environment) as a 2-D ``memoryview`` of the same shape, which supports
``mv[row, col]``, ``mv.tolist()`` and the buffer protocol.
"""

import os

if os.environ.get("PYACTAG_NO_NUMPY"):
    np = None
else:
    try:
        import numpy as np
    except ImportError:  # pragma: no cover - exercised by the no-numpy test
        np = None


def have_numpy():
    """True when results are numpy arrays."""
    return np is not None


def array2d(data, rows, cols, itemsize=1):
    """A writable 2-D array over a copy of ``data`` (native byte order)."""
    if np is not None:
        dtype = np.uint8 if itemsize == 1 else np.uint16
        return np.frombuffer(bytearray(data), dtype=dtype).reshape(rows, cols)
    return memoryview(bytearray(data)).cast("B" if itemsize == 1 else "H", (rows, cols))
