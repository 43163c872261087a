"""Families, the generator's codes, the matcher and tag images."""
import pytest

import pyactag
from conftest import DATA, GEOMETRY, detections_key, family_file_dir

np = pytest.importorskip("numpy")

BUILTIN = ("AcTag24h4", "AcTag24h6", "AcTag24h8", "AcTag24h10", "AcTag24m4", "AcTag24m6",
           "AcTag24m8", "AcTag24m10", "AcTag28m4", "AcTag28m6", "AcTag28m8", "AcTag28m10")
PUBLISHED_SIZES = {"AcTag24h4": 6261, "AcTag24h6": 453, "AcTag24h8": 45, "AcTag24h10": 7}


def test_builtin_families():
    assert pyactag.family_names() == BUILTIN
    for name in BUILTIN:
        f = pyactag.Family(name)
        bits, hamming, mirror, excluded = pyactag.rule_of_name(name)
        assert (f.name, f.bits, f.hamming, f.mirror, f.excluded) == (name, bits, hamming, mirror,
                                                                    excluded)
        assert f.builtin and len(f) == f.ncodes == len(f.codes) > 0
        assert len(set(f.codes)) == f.ncodes
        assert all(0 <= c < 2 ** f.bits for c in f.codes)
        assert f.max_corrections == (hamming // 2 - 1 if hamming % 2 == 0 else hamming // 2)
        if name in PUBLISHED_SIZES:
            assert f.ncodes == PUBLISHED_SIZES[name]
            assert f.codes[0] == 0xd35f2a  # SPEC section 3


def test_published_codes_equal_the_data_files():
    fam_dir = family_file_dir()
    if fam_dir is None:
        pytest.skip("published family files not found in {}/families or data/families".format(DATA))
    for name in PUBLISHED_SIZES:
        loaded = pyactag.Family.from_file(str(fam_dir / (name + ".txt")))
        assert loaded.codes == pyactag.Family(name).codes, name
        assert not loaded.builtin and loaded.hamming == pyactag.Family(name).hamming


def test_family_files(tmp_path):
    ref = pyactag.Family("AcTag24m6")
    txt = tmp_path / "AcTag24m6.txt"
    txt.write_text("# comment\n" + "\n".join("0x%06x" % c for c in ref.codes) + "\n")
    f = pyactag.Family.from_file(str(txt))
    assert (f.codes, f.bits, f.hamming, f.mirror, f.excluded) == (ref.codes, 24, 6, ref.mirror,
                                                                 ref.excluded)
    # The reference package's Java layout: codes as 0x...L, hamming after the layout string.
    h10 = pyactag.Family("AcTag24h10")
    java = tmp_path / "AcTag24h10.java"
    java.write_text(
        "public class AcTag24h10 extends TagFamily {\n"
        "  private static long[] constructCodes() {\n"
        "    return new long[] { " + ", ".join("0x%06xL" % c for c in h10.codes) + " };\n"
        "  }\n"
        "  public AcTag24h10() { super(ImageLayout.Factory.createFromString(\"Sonar\", \"dd\"), "
        "10, constructCodes()); }\n}\n")
    j = pyactag.Family.from_file(str(java))
    assert (j.codes, j.bits, j.hamming) == (h10.codes, 24, 10)


def test_custom_family_detects_like_builtin(example_frame):
    b = pyactag.Family("AcTag24h10")
    c = pyactag.Family.from_codes("MyTags", b.codes, bits=24, hamming=10)
    assert not c.builtin and "custom" in repr(c)
    assert (detections_key(pyactag.detect(example_frame, family=c, **GEOMETRY)) ==
            detections_key(pyactag.detect(example_frame, family=b, **GEOMETRY)))
    # Only the codes define IDs: reorder and the ID follows.
    swapped = pyactag.Family.from_codes("Swapped", (b.codes[3],) + b.codes[1:3] + (b.codes[0],) +
                                        b.codes[4:], bits=24, hamming=10)
    assert [d.id for d in pyactag.detect(example_frame, family=swapped, **GEOMETRY)] == [3]


def test_custom_family_errors():
    with pytest.raises(ValueError, match="fit in 24 bits"):
        pyactag.Family.from_codes("X", [1 << 24], bits=24, hamming=4)
    with pytest.raises(ValueError, match="multiple of 4"):
        pyactag.Family.from_codes("X", [1], bits=22, hamming=4)
    with pytest.raises(ValueError, match="at least one code"):
        pyactag.Family.from_codes("X", [], bits=24, hamming=4)
    with pytest.raises(ValueError, match="bits and hamming"):
        pyactag.Family.from_codes("X", [1])
    with pytest.raises(pyactag.ActagError) as ei:
        pyactag.Family.from_codes("X", [1], bits=24, hamming=0)
    assert ei.value.name == "ACTAG_ERR_FAMILY"
    with pytest.raises(pyactag.ActagError, match="unknown family 'AcTag24h5'"):
        pyactag.Family("AcTag24h5")
    with pytest.raises(TypeError):
        pyactag.Family("AcTag24h10", bits=24)


def test_layout_and_render():
    f = pyactag.Family("AcTag24h10")
    k = f.bits // 4
    for tag_id in range(f.ncodes):
        grid = f.layout(tag_id)
        assert len(grid) == k + 1 and all(len(r) == k + 1 for r in grid)
        # Data ring clockwise from the top-left cell, MSB first (render.h).
        ring = ([(i, 0) for i in range(k)] + [(k, i) for i in range(k)] +
                [(k - i, k) for i in range(k)] + [(0, k - i) for i in range(k)])
        code = f.codes[tag_id]
        for i, (x, y) in enumerate(ring):
            assert grid[y][x] == (code >> (f.bits - 1 - i)) & 1
        for y in range(1, k):
            for x in range(1, k):
                ring1 = x in (1, k - 1) or y in (1, k - 1)
                assert grid[y][x] == (0 if ring1 else 1)
        img = f.render(tag_id, cell_px=3, margin_px=2, margin_value=128)
        side = (k + 1) * 3 + 4
        assert img.shape == (side, side) and img.dtype == np.uint8
        assert (img[:2] == 128).all() and (img[:, -2:] == 128).all()
        cells = img[2:-2, 2:-2].reshape(k + 1, 3, k + 1, 3)
        assert (cells == (np.array(grid, np.uint8) * 255)[:, None, :, None]).all()
        cam = f.render(tag_id, cell_px=3, margin_px=2, margin_value=128, camera=True)
        assert (cam == 255 - img).all()
    assert f.render(0).shape == (70, 70)
    tabs = f.corner_tabs(0)
    assert 0 <= tabs <= 15
    with pytest.raises(pyactag.ActagError) as ei:
        f.render(f.ncodes)
    assert ei.value.name == "ACTAG_ERR_FAMILY"
    with pytest.raises(pyactag.ActagError) as ei:
        f.render(0, cell_px=0)
    assert ei.value.name == "ACTAG_ERR_PARAM"


def test_corner_tabs_rule():
    f = pyactag.Family("AcTag24h6")
    k = f.bits // 4
    corners = {pyactag.CORNER_TOP_LEFT: (0, 0), pyactag.CORNER_TOP_RIGHT: (k, 0),
               pyactag.CORNER_BOTTOM_RIGHT: (k, k), pyactag.CORNER_BOTTOM_LEFT: (0, k)}
    for tag_id in range(40):
        g = f.layout(tag_id)
        expect = 0
        for bit, (x, y) in corners.items():
            nx = (1 if x == 0 else k - 1, y)
            ny = (x, 1 if y == 0 else k - 1)
            if g[y][x] == 0 and g[nx[1]][nx[0]] == 1 and g[ny[1]][ny[0]] == 1:
                expect |= bit
        assert f.corner_tabs(tag_id) == expect, tag_id


def test_matcher_and_code_helpers():
    f = pyactag.Family("AcTag24h10")
    for tag_id, code in enumerate(f.codes):
        assert f.match(code) == {"id": tag_id, "rotation": 0, "mirrored": False, "hamming": 0}
        r = code
        for rot in range(1, 4):
            r = pyactag.code_rot90(r, 24)
            m = f.match(r)
            assert (m["id"], m["rotation"], m["mirrored"]) == (tag_id, rot, False)
        assert pyactag.code_rot90(r, 24) == code
        m = f.match(pyactag.code_reverse(code, 24))
        assert (m["id"], m["mirrored"]) == (tag_id, True)
        assert f.match(pyactag.code_reverse(code, 24), rotations_only=True) is None or \
            f.match(pyactag.code_reverse(code, 24), rotations_only=True)["mirrored"] is False
        flipped = code ^ 0b1011  # 3 bit errors
        m = f.match(flipped)
        assert (m["id"], m["hamming"]) == (tag_id, 3)
        assert f.match(flipped, max_corrections=2) is None
        assert pyactag.code_mirror(pyactag.code_mirror(code, 24), 24) == code
    with pytest.raises(ValueError):
        f.match(1 << 24)
