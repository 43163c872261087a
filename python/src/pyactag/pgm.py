"""Binary PGM (P5) frames, 8 or 16 bit, as 2-D arrays."""

import sys
from array import array

from ._arrays import array2d


def _token(data, pos):
    n = len(data)
    while pos < n:
        c = data[pos:pos + 1]
        if c == b"#":
            while pos < n and data[pos:pos + 1] not in (b"\n", b"\r"):
                pos += 1
        elif c in (b" ", b"\t", b"\n", b"\r", b"\v", b"\f"):
            pos += 1
        else:
            break
    start = pos
    while pos < n and data[pos:pos + 1].isdigit():
        pos += 1
    if start == pos:
        raise ValueError("bad PGM header")
    return int(data[start:pos]), pos


def parse_pgm(data, name="<bytes>"):
    """A binary PGM image (bytes) -> 2-D uint8 (maxval <= 255) or uint16
    array (numpy if available, else a 2-D memoryview), rows x cols."""
    if data[:2] != b"P5":
        raise ValueError("{}: not a binary PGM (P5) file".format(name))
    try:
        cols, pos = _token(data, 2)
        rows, pos = _token(data, pos)
        maxval, pos = _token(data, pos)
    except ValueError:
        raise ValueError("{}: bad PGM header".format(name)) from None
    if not (1 <= cols <= 32767 and 1 <= rows <= 32767 and 1 <= maxval <= 65535):
        raise ValueError("{}: PGM size {} x {} or maxval {} out of range".format(
            name, cols, rows, maxval))
    pos += 1  # the single whitespace after maxval
    itemsize = 2 if maxval > 255 else 1
    need = rows * cols * itemsize
    pixels = data[pos:pos + need]
    if len(pixels) < need:
        raise ValueError("{}: PGM file is shorter than its header says".format(name))
    if itemsize == 2:  # PGM samples are big-endian
        a = array("H")
        a.frombytes(pixels)
        if sys.byteorder == "little":
            a.byteswap()
        pixels = a.tobytes()
    return array2d(pixels, rows, cols, itemsize)


def read_pgm(path):
    """Read a binary PGM file (see ``parse_pgm``)."""
    with open(path, "rb") as f:
        return parse_pgm(f.read(), str(path))


def write_pgm(path, image):
    """Write a 2-D uint8 or uint16 array as binary PGM."""
    mv = memoryview(image)
    if mv.ndim != 2 or mv.format not in ("B", "H", "<H", "=H", "@H"):
        raise ValueError("write_pgm needs a 2-D uint8 or uint16 array")
    rows, cols = mv.shape
    data = mv.tobytes()
    maxval = 255
    if mv.itemsize == 2:
        a = array("H")
        a.frombytes(data)
        if sys.byteorder == "little":
            a.byteswap()
        data = a.tobytes()
        maxval = 65535
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n%d\n" % (cols, rows, maxval))
        f.write(data)
