"""PGM files are read as the C tools read them (tools/hostio/hostio.c): the
same pixels, hence the same detections, and the same refusals."""
import array
from pathlib import Path

import pytest

import pyactag
from conftest import GEOMETRY, TAG_SIZE, assert_same_as_c, run_c_tool

np = pytest.importorskip("numpy")


def pgm(cols, rows, maxval, pixels):
    return b"P5\n%d %d\n%d\n" % (cols, rows, maxval) + bytes(pixels)


def test_low_maxval_scaled_as_the_c_tool(example_frame, c_tool, tmp_path):
    # An 8-bit PGM of maxval 100: samples scaled to 0..255, rounded, as in C.
    v = (example_frame.astype(np.uint32) * 100 // 255).astype(np.uint8)
    path = tmp_path / "maxval100.pgm"
    path.write_bytes(pgm(620, 463, 100, v.tobytes()))
    f = pyactag.read_pgm(path)
    assert f.dtype == np.uint8
    assert np.array_equal(f, ((v.astype(np.uint32) * 255 + 50) // 100).astype(np.uint8))
    line = run_c_tool(c_tool, [path])[0]
    assert line["detections"]  # the tag is found, with the C tool's margin
    assert_same_as_c(pyactag.detect(f, tag_size=TAG_SIZE, **GEOMETRY), line, "maxval 100")
    assert pyactag.parse_pgm(pgm(3, 1, 2, [0, 1, 2])).tolist() == [[0, 128, 255]]


def test_sixteen_bit_samples_as_stored(example_frame, c_tool, tmp_path):
    f16 = example_frame.astype(np.uint16) * 3 + 1  # maxval 1000: not scaled
    path = tmp_path / "maxval1000.pgm"
    path.write_bytes(pgm(620, 463, 1000, f16.astype(">u2").tobytes()))
    got = pyactag.read_pgm(path)
    assert got.dtype == np.uint16 and np.array_equal(got, f16)
    assert_same_as_c(pyactag.detect(got, tag_size=TAG_SIZE, **GEOMETRY),
                     run_c_tool(c_tool, [path])[0], "maxval 1000")


def test_refusals_name_the_file_and_the_fault(tmp_path):
    path = tmp_path / "bad.pgm"
    path.write_bytes(pgm(3, 2, 100, [0, 1, 2, 3, 4, 101]))
    with pytest.raises(ValueError, match=r"bad.pgm: PGM sample 101 at row 1, column 2 is above "
                                         r"maxval 100"):
        pyactag.read_pgm(path)
    with pytest.raises(ValueError, match=r"bad.pgm: PGM sample 1001 at row 0, column 1"):
        pyactag.parse_pgm(pgm(2, 1, 1000, [0, 5, 0x03, 0xE9]), "bad.pgm")
    with pytest.raises(ValueError, match=r"3 bytes after the PGM's 6 pixel bytes \(one frame "
                                         r"per file\)"):
        pyactag.parse_pgm(pgm(3, 2, 255, [0] * 9))
    with pytest.raises(ValueError, match="PGM has 5 pixel bytes, its header needs 6"):
        pyactag.parse_pgm(pgm(3, 2, 255, [0] * 5))
    for header, message in ((b"P5\n3 x\n255\n", "PGM height 'x' is not a whole number in "
                                                "1..32767"),
                            (b"P5\n0 2\n255\n", "PGM width '0' is not a whole number"),
                            (b"P5\n-3 2\n255\n", "PGM width '-3' is not a whole number"),
                            (b"P5\n3 2\n70000\n", "PGM maxval '70000' is not a whole number in "
                                                  "1..65535"),
                            (b"P5\n3 2\n2.5e2\n", "PGM maxval '2.5e2'"),
                            (b"P5\n3 2\n" + b"9" * 30 + b"\n",
                             "PGM maxval '" + "9" * 20 + r"\.\.\.'"),
                            (b"P5\n3 2\n255x\n", "PGM maxval '255x' is not a whole number"),
                            (b"P6\n3 2\n255\n", "P6 image: only binary PGM"),
                            (b"P5x3 2\n255\n", r"no P5 magic; it starts 'P5x3 2\\n2\.\.\.'")):
        with pytest.raises(ValueError, match=message):
            pyactag.parse_pgm(header + bytes(6))
    with pytest.raises(ValueError, match="PGM maxval missing"):
        pyactag.parse_pgm(b"P5\n3 2 # no maxval")
    with pytest.raises(ValueError, match="header ends without pixel data"):
        pyactag.parse_pgm(b"P5\n3 2\n255")
    with pytest.raises(ValueError, match="no P5 magic; it is empty"):
        pyactag.parse_pgm(b"")
    # What C accepts: comments (one right after maxval too, as Netpbm),
    # leading zeros, CR between fields.
    assert pyactag.parse_pgm(b"P5\n3 2\n255#x\n" + bytes(range(6))).tolist() == [
        [0, 1, 2], [3, 4, 5]]
    assert pyactag.parse_pgm(b"P5 # c\n003\r2 #x\n0255\n" + bytes(range(6))).tolist() == [
        [0, 1, 2], [3, 4, 5]]


def test_bytes_like_and_paths(tmp_path):
    data = pgm(3, 2, 255, range(6))
    expected = [[0, 1, 2], [3, 4, 5]]
    for obj in (data, bytearray(data), memoryview(data), array.array("B", data)):
        assert pyactag.parse_pgm(obj).tolist() == expected
    with pytest.raises(TypeError, match="bytes-like"):
        pyactag.parse_pgm(data.decode("latin-1"))
    path = tmp_path / "p.pgm"
    pyactag.write_pgm(path, pyactag.parse_pgm(data))  # a pathlib.Path
    assert pyactag.read_pgm(Path(str(path))).tolist() == expected
    assert pyactag.read_pgm(str(path)).tolist() == expected
    assert pyactag.read_pgm(bytes(path)).tolist() == expected


def test_write_pgm_byte_orders_and_refusals(tmp_path):
    a = np.array([[1, 256, 65535], [0, 2, 513]], np.uint16)
    expected = pgm(3, 2, 65535, a.astype(">u2").tobytes())
    for dtype in ("<u2", ">u2", np.uint16):
        path = tmp_path / "w.pgm"
        pyactag.write_pgm(path, a.astype(dtype))
        assert path.read_bytes() == expected, dtype
        assert np.array_equal(pyactag.read_pgm(path), a)
    pyactag.write_pgm(path, a.astype(">u2")[:, ::2])  # strided
    assert np.array_equal(pyactag.read_pgm(path), a[:, ::2])
    for shape in ((0, 5), (5, 0), (0, 0)):
        with pytest.raises(ValueError, match="1..32767 rows and columns"):
            pyactag.write_pgm(tmp_path / "e.pgm", np.zeros(shape, np.uint8))
    with pytest.raises(TypeError, match="uint8 or uint16"):
        pyactag.write_pgm(tmp_path / "e.pgm", np.zeros((2, 2), np.float32))
    with pytest.raises(ValueError, match="2-D"):
        pyactag.write_pgm(tmp_path / "e.pgm", np.zeros((2, 2, 2), np.uint8))
    assert not (tmp_path / "e.pgm").exists()
