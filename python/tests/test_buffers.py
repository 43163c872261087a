"""Frames of every layout give the same detections: strided and
non-contiguous numpy views, byte orders, misaligned data, plain buffers."""
import array

import pytest

import pyactag
from conftest import GEOMETRY, detections_key

np = pytest.importorskip("numpy")


@pytest.fixture(scope="module")
def reference(example_frame):
    return detections_key(pyactag.detect(example_frame, **GEOMETRY))


def same(frame, reference):
    assert detections_key(pyactag.detect(frame, **GEOMETRY)) == reference


def test_row_strided_view(example_frame, reference):
    big = np.zeros((600, 700), np.uint8)
    big[17:17 + 463, 33:33 + 620] = example_frame
    view = big[17:17 + 463, 33:33 + 620]
    assert not view.flags.c_contiguous and view.strides == (700, 1)
    same(view, reference)


def test_column_strided_view(example_frame, reference):
    wide = np.repeat(example_frame, 3, axis=1)
    view = wide[:, 1::3]
    assert view.strides == (3 * 620, 3)
    same(view, reference)


def test_fortran_order(example_frame, reference):
    f = np.asfortranarray(example_frame)
    assert not f.flags.c_contiguous
    same(f, reference)


def test_negative_strides(example_frame):
    view = example_frame[::-1, ::-1]
    assert view.strides[0] < 0
    expected = detections_key(pyactag.detect(np.ascontiguousarray(view), **GEOMETRY))
    assert detections_key(pyactag.detect(view, **GEOMETRY)) == expected


def test_transposed_is_a_different_frame(example_frame):
    t = example_frame.T  # 620 rows x 463 columns, a view
    expected = detections_key(pyactag.detect(np.ascontiguousarray(t), **GEOMETRY))
    assert detections_key(pyactag.detect(t, **GEOMETRY)) == expected


def test_read_only(example_frame, reference):
    f = example_frame.copy()
    f.setflags(write=False)
    same(f, reference)


def test_uint16_orders_and_alignment(example_frame):
    f16 = example_frame.astype(np.uint16) * 200
    expected = detections_key(pyactag.detect(f16, **GEOMETRY))
    assert expected  # 16-bit frames find the tag too
    assert detections_key(pyactag.detect(f16.astype(">u2"), **GEOMETRY)) == expected
    assert detections_key(pyactag.detect(f16.astype("<u2"), **GEOMETRY)) == expected
    raw = bytearray(f16.size * 2 + 1)
    odd = np.frombuffer(raw, dtype=np.uint16, count=f16.size, offset=1).reshape(f16.shape)
    odd[...] = f16
    assert odd.ctypes.data % 2 == 1
    assert detections_key(pyactag.detect(odd, **GEOMETRY)) == expected
    assert detections_key(pyactag.detect(f16[:, ::-1][:, ::-1], **GEOMETRY)) == expected


def test_buffer_protocol_objects(example_frame, reference):
    raw = example_frame.tobytes()
    same(memoryview(raw).cast("B", example_frame.shape), reference)
    same(memoryview(bytearray(raw)).cast("B", example_frame.shape), reference)
    a = array.array("B", raw)
    same(memoryview(a).cast("B", example_frame.shape), reference)
    a16 = array.array("H", (example_frame.astype(np.uint16) * 200).ravel().tolist())
    mv16 = memoryview(a16).cast("B").cast("H", example_frame.shape)
    expected16 = detections_key(pyactag.detect(example_frame.astype(np.uint16) * 200, **GEOMETRY))
    assert expected16
    assert detections_key(pyactag.detect(mv16, **GEOMETRY)) == expected16
    # Byte orders through the buffer protocol (a memoryview has no
    # __array_interface__): big-endian ('>H') is swapped, native ('H') is not.
    f16 = example_frame.astype(np.uint16) * 200
    for order, fmt in ((">u2", ">H"), ("=u2", "H")):
        mv = memoryview(f16.astype(order))
        assert mv.format == fmt and not hasattr(mv, "__array_interface__")
        assert detections_key(pyactag.detect(mv, **GEOMETRY)) == expected16, order
    # A strided memoryview (non-contiguous): copied through tobytes().
    wide = np.repeat(example_frame, 2, axis=1)
    mv = memoryview(wide[:, ::2])  # a strided buffer, no __array_interface__
    assert not mv.c_contiguous and not hasattr(mv, "__array_interface__")
    same(mv, reference)


class ArrayInterfaceOnly:
    """An object that exposes only __array_interface__ (like Pillow images)."""

    def __init__(self, arr):
        self._arr = arr
        self.__array_interface__ = arr.__array_interface__


def test_array_interface_object(example_frame, reference):
    same(ArrayInterfaceOnly(example_frame), reference)
    big = np.zeros((500, 650), np.uint8)
    big[:463, :620] = example_frame
    same(ArrayInterfaceOnly(big[:463, :620]), reference)


def test_array_interface_with_numpy_integers(example_frame, reference):
    # A valid 2-D __array_interface__ whose shape holds numpy integers was
    # refused as "frame must be 2-D, not 2-D" (review): any integer is taken
    # (__index__), and a shape that is wrong says what is wrong.
    view = example_frame[:, ::2]  # strided: the strides are read too
    expected = detections_key(pyactag.detect(view, **GEOMETRY))
    for kind in (np.int64, np.uint16, np.intp):
        obj = ArrayInterfaceOnly(example_frame)
        obj.__array_interface__ = dict(obj.__array_interface__,
                                       shape=tuple(kind(n) for n in example_frame.shape))
        same(obj, reference)
        obj = ArrayInterfaceOnly(view)
        obj.__array_interface__ = dict(obj.__array_interface__,
                                       shape=tuple(kind(n) for n in view.shape),
                                       strides=tuple(np.int64(n) for n in view.strides))
        assert detections_key(pyactag.detect(obj, **GEOMETRY)) == expected
    same(PillowLike(example_frame, offset=np.int64(0)), reference)
    bad = ArrayInterfaceOnly(example_frame)
    bad.__array_interface__ = dict(bad.__array_interface__, shape=(463.0, 620))
    with pytest.raises(TypeError, match=r"shape must be 2 integers, got \(463.0, 620\)"):
        pyactag.detect(bad, **GEOMETRY)
    bad.__array_interface__["shape"] = (463, 2 ** 70)
    with pytest.raises(ValueError, match="rows and columns must be 1"):
        pyactag.detect(bad, **GEOMETRY)
    bad.__array_interface__["shape"] = (463, 620, np.int64(1))
    with pytest.raises(ValueError, match="frame must be 2-D, not 3-D"):
        pyactag.detect(bad, **GEOMETRY)


def test_index_that_empties_the_array_interface(example_frame):
    # The entries are held while a shape entry's __index__ runs Python code
    # (here it empties the dict they are borrowed from).
    obj = ArrayInterfaceOnly(example_frame)
    ai = dict(obj.__array_interface__)

    class Rows:
        def __index__(self):
            ai.clear()
            return example_frame.shape[0]

    ai["shape"] = (Rows(), example_frame.shape[1])
    obj.__array_interface__ = ai
    assert detections_key(pyactag.detect(obj, **GEOMETRY)) == detections_key(
        pyactag.detect(example_frame, **GEOMETRY))


def test_input_is_not_modified(example_frame):
    f = example_frame.copy()
    pyactag.detect(f, **GEOMETRY)
    assert np.array_equal(f, example_frame)


class PillowLike:
    """__array_interface__ with the pixels as a bytes object (what Pillow gives)."""

    def __init__(self, arr, offset=0):
        self.__array_interface__ = {"shape": arr.shape, "typestr": arr.dtype.str,
                                    "version": 3, "data": b"\0" * offset + arr.tobytes(),
                                    "offset": offset}


def test_array_interface_with_bytes(example_frame, reference):
    same(PillowLike(example_frame), reference)
    same(PillowLike(example_frame, offset=3), reference)
    f16 = example_frame.astype(np.uint16) * 200
    expected = detections_key(pyactag.detect(f16, **GEOMETRY))
    assert detections_key(pyactag.detect(PillowLike(f16, offset=1), **GEOMETRY)) == expected
    short = PillowLike(example_frame)
    short.__array_interface__["data"] = short.__array_interface__["data"][:-1]
    with pytest.raises(TypeError, match="smaller than its shape"):
        pyactag.detect(short, **GEOMETRY)
    # strides so large that shape x stride wrapped round the check (a segfault)
    for shape, strides in (((3, 1), (2 ** 62, 1)), ((2, 2), (2 ** 63 - 1, 2 ** 63 - 1)),
                           ((2, 2), (-(2 ** 62), 1))):
        huge = PillowLike(example_frame)
        huge.__array_interface__.update(shape=shape, strides=strides, typestr="|u1",
                                        data=bytes(64))
        with pytest.raises(TypeError, match="smaller than its shape"):
            pyactag.detect(huge, **GEOMETRY)


def test_masked_array_refused(example_frame):
    # the mask is not in __array_interface__: the masked pixels were read
    m = np.ma.masked_array(np.asarray(example_frame), mask=False)
    with pytest.raises(TypeError, match="masked arrays are not supported"):
        pyactag.detect(m, **GEOMETRY)


def test_palette_image_refused(example_frame):
    Image = pytest.importorskip("PIL.Image")
    img = Image.fromarray(np.asarray(example_frame)).convert("P")
    with pytest.raises(TypeError, match="palette image"):
        pyactag.detect(img, **GEOMETRY)
    # the grey conversion is read as usual
    assert pyactag.detect(img.convert("L"), **GEOMETRY)
