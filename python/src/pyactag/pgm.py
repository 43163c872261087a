"""Binary PGM (P5) frames, 8 or 16 bit, as 2-D arrays.

Read as the C tools read them (tools/hostio/hostio.c): one frame per file,
every sample <= maxval, 8-bit samples of a maxval below 255 scaled to
0..255 (v * 255 / maxval, rounded), 16-bit samples as stored."""

import os
import sys
from array import array

from ._arrays import array2d

_SPACE = b" \t\n\r"


def _quote_start(data):
    """The first bytes of data (at most 8) as the C tools quote them:
    printable ASCII as it is, backslash and quote escaped, \\n \\r \\t, other
    bytes as \\xHH; '...' when there are more."""
    out = []
    for c in bytes(data[:8]):
        if c in (0x5C, 0x27):
            out.append("\\" + chr(c))
        elif c in (0x0A, 0x0D, 0x09):
            out.append({0x0A: "\\n", 0x0D: "\\r", 0x09: "\\t"}[c])
        elif 0x20 <= c < 0x7F:
            out.append(chr(c))
        else:
            out.append("\\x%02x" % c)
    return "".join(out) + ("..." if len(data) > 8 else "")


def _field(data, pos, name, what, lo, hi):
    """The next header field (after whitespace and '#' comments) as an
    integer in lo..hi, and the position after it; ValueError quoting the
    text found (hostio.c's pgm_field)."""
    n = len(data)
    while pos < n:
        if data[pos] == 0x23:  # '#': a comment to the end of the line
            while pos < n and data[pos] != 0x0A:
                pos += 1
        elif data[pos] in _SPACE:
            pos += 1
        else:
            break
    start = pos
    while pos < n and data[pos] not in _SPACE and data[pos] != 0x23:
        pos += 1
    if pos == start:
        raise ValueError("{}: PGM {} missing (the header ends)".format(name, what))
    text = data[start:pos]
    digits = text.lstrip(b"0") or b"0"  # leading zeros are allowed, as in C
    if text.isdigit() and len(digits) <= 6 and lo <= int(digits) <= hi:
        return int(digits), pos
    shown = "".join(chr(c) if 0x20 <= c < 0x7F else "?" for c in text[:20])
    if len(text) > 20:
        shown += "..."
    raise ValueError("{}: PGM {} '{}' is not a whole number in {}..{}".format(
        name, what, shown, lo, hi))


def parse_pgm(data, name="<bytes>"):
    """A binary PGM image (any bytes-like object) -> 2-D uint8 (maxval <=
    255) or uint16 array (numpy if available, else a 2-D memoryview), rows x
    cols, decoded as the C tools do: 8-bit samples of a maxval below 255
    scaled to 0..255 ((v * 255 + maxval // 2) // maxval), 16-bit samples as
    stored. ValueError (starting with ``name``) for a malformed header, a
    sample above maxval, missing pixel bytes or bytes after them."""
    try:
        data = data if isinstance(data, bytes) else memoryview(data).tobytes()
    except TypeError:
        raise TypeError("{}: PGM data must be a bytes-like object, not {}".format(
            name, type(data).__name__)) from None
    if len(data) >= 2 and data[0:1] == b"P" and data[1:2] in b"1234567" and data[1:2] != b"5":
        raise ValueError("{}: a P{} image: only binary PGM (P5) is supported".format(
            name, data[1:2].decode()))
    if len(data) < 3 or data[:2] != b"P5" or data[2] not in b" \t\n\r#":
        if len(data) == 0:
            raise ValueError("{}: not a binary PGM (no P5 magic; it is empty)".format(name))
        raise ValueError("{}: not a binary PGM (no P5 magic; it starts '{}')".format(
            name, _quote_start(data)))
    cols, pos = _field(data, 2, name, "width", 1, 32767)
    rows, pos = _field(data, pos, name, "height", 1, 32767)
    maxval, pos = _field(data, pos, name, "maxval", 1, 65535)
    if pos < len(data) and data[pos] == 0x23:
        # a comment right after maxval (Netpbm reads one there, as the C
        # tools do): its end of line is the single whitespace before the pixels
        end = data.find(b"\n", pos)
        pos = len(data) if end < 0 else end
    if pos >= len(data):
        raise ValueError("{}: PGM header ends without pixel data".format(name))
    if data[pos] not in _SPACE:
        raise ValueError("{}: PGM maxval is not followed by whitespace".format(name))
    pos += 1  # the single whitespace after maxval
    itemsize = 2 if maxval > 255 else 1
    need = rows * cols * itemsize
    have = len(data) - pos
    if have < need:
        raise ValueError("{}: PGM has {} pixel bytes, its header needs {}".format(
            name, have, need))
    if have > need:  # more frames, or junk: nothing is dropped silently
        raise ValueError("{}: {} bytes after the PGM's {} pixel bytes (one frame per file)"
                         .format(name, have - need, need))
    pixels = data[pos:]
    samples = pixels
    if itemsize == 2:  # PGM samples are big-endian
        samples = array("H")
        samples.frombytes(pixels)
        if sys.byteorder == "little":
            samples.byteswap()
        pixels = samples.tobytes()
    if max(samples) > maxval:
        i = next(i for i, s in enumerate(samples) if s > maxval)
        raise ValueError("{}: PGM sample {} at row {}, column {} is above maxval {}".format(
            name, samples[i], i // cols, i % cols, maxval))
    if itemsize == 1 and maxval != 255:
        pixels = pixels.translate(bytes((min(v, maxval) * 255 + maxval // 2) // maxval
                                        for v in range(256)))
    return array2d(pixels, rows, cols, itemsize)


def read_pgm(path):
    """Read a binary PGM file (a str or ``os.PathLike`` path; see ``parse_pgm``)."""
    with open(path, "rb") as f:
        return parse_pgm(f.read(), os.fsdecode(path))


def write_pgm(path, image):
    """Write a 2-D uint8 (maxval 255) or uint16 (maxval 65535, any byte
    order) array of 1..32767 rows and columns as binary PGM."""
    mv = memoryview(image)
    fmt = mv.format
    order = fmt[0] if fmt[:1] in ("<", ">", "!", "=", "@") else "@"
    if fmt.lstrip("<>!=@") not in ("B", "H"):
        raise TypeError("write_pgm needs a uint8 or uint16 array, not format {!r}".format(fmt))
    if mv.ndim != 2:
        raise ValueError("write_pgm needs a 2-D array, not {} dimensions".format(mv.ndim))
    rows, cols = mv.shape
    if not (1 <= rows <= 32767 and 1 <= cols <= 32767):
        raise ValueError("write_pgm: a PGM has 1..32767 rows and columns, the array {} x {}"
                         .format(rows, cols))
    data = mv.tobytes()
    maxval = 255
    if mv.itemsize == 2:
        big = order in (">", "!") or (order in ("@", "=") and sys.byteorder == "big")
        if not big:  # PGM samples are big-endian
            a = array("H")
            a.frombytes(data)
            a.byteswap()
            data = a.tobytes()
        maxval = 65535
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n%d\n" % (cols, rows, maxval))
        f.write(data)
