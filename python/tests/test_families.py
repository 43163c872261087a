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


def test_tag_id_and_render_arguments_named():
    f = pyactag.Family("AcTag24h10")
    msg = r"tag ID {} is outside 0\.\.6 \(family AcTag24h10 has 7 codes\)"
    for call, bad in ((lambda: f.render(99), 99), (lambda: f.layout(-1), -1),
                      (lambda: f.corner_tabs(7), 7), (lambda: f.layout_cell(7, 0, 0), 7),
                      (lambda: f.render(f.ncodes), 7)):
        with pytest.raises(ValueError, match=msg.format(bad)) as ei:
            call()
        assert not isinstance(ei.value, pyactag.ActagError)
    for kw, message in ((dict(cell_px=0), r"cell_px must be 1\.\.32767, got 0"),
                        (dict(margin_px=-1), r"margin_px must be 0\.\.32767, got -1"),
                        (dict(margin_value=300), r"margin_value must be 0\.\.255, got 300"),
                        (dict(cell_px=5000), "cell_px 5000 and margin_px 0 make an image of "
                                             "side 35000 pixels")):
        with pytest.raises(ValueError, match=message):
            f.render(0, **kw)
    with pytest.raises(ValueError, match=r"x must be 0\.\.6, got 7"):
        f.layout_cell(0, 7, 0)
    for kw, message in ((dict(cell_px=2.5), "cell_px must be an integer, got 2.5"),
                        (dict(margin_value="0"), "margin_value must be an integer, got '0'"),
                        (dict(camera="False"), "camera must be a bool, got 'False'")):
        with pytest.raises(TypeError, match=message):
            f.render(0, **kw)
    with pytest.raises(TypeError, match="tag ID must be an integer, got 1.0"):
        f.render(1.0)
    assert f.render(np.int64(1), cell_px=np.uint8(3), camera=np.bool_(True)).shape == (21, 21)


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
    # checked, not converted: "False" is truthy, True would be 1 correction
    w = pyactag.code_reverse(f.codes[3], 24)
    with pytest.raises(TypeError, match="rotations_only must be a bool"):
        f.match(w, rotations_only="False")
    with pytest.raises(TypeError, match="max_corrections must be an integer"):
        f.match(w, max_corrections=True)
    with pytest.raises(ValueError, match="max_corrections must be -1"):
        f.match(w, max_corrections=33)
    assert f.match(w, rotations_only=False)["id"] == 3
    assert f.match(w, max_corrections=np.int64(0))["id"] == 3


def test_codes_do_not_wrap():
    f = pyactag.Family("AcTag24h10")
    c = f.codes[3]
    with pytest.raises(ValueError, match=r"word must fit in 24 bits \(0\.\.0xffffff\), got "
                                         + str(2 ** 64 + c)):
        f.match(2 ** 64 + c)
    with pytest.raises(ValueError, match="word must fit in 24 bits"):
        f.match(-1)
    for fn in (pyactag.code_rot90, pyactag.code_reverse, pyactag.code_mirror):
        with pytest.raises(ValueError, match="code must fit in 24 bits"):
            fn(2 ** 64 + c, 24)
        with pytest.raises(ValueError, match="code must fit in 24 bits"):
            fn(-c, 24)
        with pytest.raises(TypeError, match="code must be an integer, got True"):
            fn(True, 24)
    assert pyactag.code_rot90(np.uint32(c), 24) == pyactag.code_rot90(c, 24)
    assert pyactag.code_reverse(2 ** 32 - 1, 32) == 2 ** 32 - 1
    with pytest.raises(TypeError, match="word must be an integer, got 1.0"):
        f.match(1.0)
    with pytest.raises(ValueError, match=r"codes\[1\] must fit in 24 bits"):
        pyactag.Family.from_codes("X", [1, 2 ** 64 + 1], bits=24, hamming=4)
    with pytest.raises(ValueError, match=r"codes\[0\] must fit in 24 bits"):
        pyactag.Family.from_codes("X", [-1], bits=24, hamming=4)
    with pytest.raises(ValueError, match="excluded must fit in 24 bits"):
        pyactag.Family.from_codes("X", [1], bits=24, hamming=4, excluded=2 ** 64 + 1)


def test_family_files_as_path_objects(tmp_path):
    f = pyactag.Family("AcTag24h10")
    path = tmp_path / "AcTag24h10.txt"
    path.write_text("\n".join(hex(c) for c in f.codes) + "\n")
    assert pyactag.Family.from_file(path).codes == f.codes  # a pathlib.Path
    assert pyactag.Family.from_file(bytes(path)).codes == f.codes
    # A name that does not say bits and hamming: the message says how to give them.
    mine = tmp_path / "mine.txt"
    mine.write_text(path.read_text())
    with pytest.raises(ValueError, match="name 'mine' does not say bits and hamming.*pass bits= "
                                         "and hamming="):
        pyactag.Family.from_file(mine)
    m = pyactag.Family.from_file(mine, bits=24, hamming=10)
    assert (m.name, m.codes, m.bits, m.hamming) == ("mine", f.codes, 24, 10)
    bad = tmp_path / "AcTag24h10b.txt"
    bad.write_text("0x123\nzz\n")
    with pytest.raises(ValueError, match=r"AcTag24h10b.txt:2: 'zz' is not a code"):
        pyactag.Family.from_file(bad, bits=24, hamming=10)
    with pytest.raises(ValueError, match="not AcTag"):
        pyactag.rule_of_name("AcTag24h10\n")


def test_pickle_families():
    import pickle
    b = pyactag.Family("AcTag28m4")
    c = pickle.loads(pickle.dumps(b))
    assert c.builtin and c.name == b.name and c.codes == b.codes
    custom = pyactag.Family.from_codes("MyTags", b.codes[:50], bits=28, hamming=4, mirror=1,
                                       excluded=pyactag.Family("AcTag28m4").excluded)
    d = pickle.loads(pickle.dumps(custom))
    assert (not d.builtin and d.name == "MyTags" and d.codes == custom.codes and
            (d.bits, d.hamming, d.mirror, d.excluded) ==
            (custom.bits, custom.hamming, custom.mirror, custom.excluded))
