"""Tag families: the built-in code tables, families from code lists or
files, and tag images."""

import os
import re

from . import _core
from ._args import as_bool, as_int
from ._arrays import array2d

_NAME_RULE = re.compile(r"AcTag(\d+)([hmp])(\d+)\Z")


def family_names():
    """Names of the families compiled into the library (ACTAG_FAMILIES)."""
    return _core.family_names()


def rule_of_name(name):
    """(bits, hamming, mirror, excluded) that an AcTag<bits>[hmp]<h> name
    stands for (docs/families.md): h = published rule (full bit reversal),
    m = mirror-safe (physical reflection, corner cells excluded), p =
    physical reflection over all cells. ValueError for other names."""
    m = _NAME_RULE.match(name)
    if not m:
        raise ValueError("family name '{}' is not AcTag<bits>h|m|p<hamming>".format(name))
    bits, kind, hamming = int(m.group(1)), m.group(2), int(m.group(3))
    if kind == "h":
        return bits, hamming, _core.MIRROR_REVERSE, 0
    if kind == "m":
        return bits, hamming, _core.MIRROR_PHYSICAL, _core.code_corners(bits)
    return bits, hamming, _core.MIRROR_PHYSICAL, 0


class Family(_core.Family):
    """An AcTag family: ``Family("AcTag24h10")`` for a built-in one.

    Attributes: name, bits, hamming, ncodes (also ``len()``), codes (in ID
    order, most significant bit = top-left cell as printed, clockwise),
    mirror, excluded, builtin, max_corrections.
    """

    def __reduce__(self):
        """Pickling (multiprocessing, caches): a built-in family by its name,
        any other by its codes and rule."""
        if self.builtin:
            return (type(self), (self.name,))
        return (type(self), (self.name, list(self.codes), self.bits, self.hamming, self.mirror,
                             self.excluded))

    @classmethod
    def from_codes(cls, name, codes, bits=None, hamming=None, mirror=None, excluded=None):
        """A family of caller-supplied codes (e.g. from ``actag-familygen``).

        bits/hamming/mirror/excluded default to what the name stands for
        (``rule_of_name``) when it is AcTag<bits>[hmp]<h>.
        """
        if None in (bits, hamming, mirror, excluded):
            try:
                b, h, mi, ex = rule_of_name(name)
            except ValueError:
                if bits is None or hamming is None:
                    raise ValueError("name '{}' does not say bits and hamming (it is not "
                                     "AcTag<bits>h|m|p<hamming>); pass bits= and hamming="
                                     .format(name)) from None
                b, h, mi, ex = bits, hamming, _core.MIRROR_REVERSE, 0
            bits = b if bits is None else bits
            hamming = h if hamming is None else hamming
            mirror = mi if mirror is None else mirror
            excluded = ex if excluded is None else excluded
        return cls(name, list(codes), bits, hamming, mirror, excluded)

    @classmethod
    def from_file(cls, path, name=None, bits=None, hamming=None):
        """Load a family file (a str or ``os.PathLike`` path):
        ``actag-familygen --format txt`` output (one 0x code per line, '#'
        comments), or the reference package's ``AcTag24h10.java`` (its
        hamming is read from the file). The name defaults to the file name
        without its extension; bits and hamming default to what the name
        stands for (``rule_of_name``), else pass them."""
        path = os.fsdecode(path)
        with open(path, "r", encoding="utf-8") as f:
            text = f.read()
        stem = os.path.splitext(os.path.basename(path))[0]
        name = stem if name is None else name
        if path.endswith(".java"):
            codes = [int(h, 16) for h in re.findall(r"0x([0-9a-fA-F]+)L", text)]
            m = re.search(r"\)\s*,\s*(\d+)\s*,\s*constructCodes\(\)", text)
            if hamming is None and m:
                hamming = int(m.group(1))
            return cls.from_codes(name, codes, bits=bits, hamming=hamming)
        codes = []
        for n, line in enumerate(text.splitlines(), 1):
            line = line.split("#", 1)[0].strip()
            if line:
                try:
                    codes.append(int(line, 0))
                except ValueError:
                    raise ValueError("{}:{}: '{}' is not a code (0x... or a whole number)".format(
                        path, n, line)) from None
        return cls.from_codes(name, codes, bits=bits, hamming=hamming)

    def _tag_id(self, id):
        """``id`` checked against the family's IDs (ValueError naming it)."""
        try:
            return as_int("tag ID", id, 0, self.ncodes - 1)
        except ValueError:
            raise ValueError("tag ID {} is outside 0..{} (family {} has {} codes)".format(
                id, self.ncodes - 1, self.name, self.ncodes)) from None

    def render(self, id, cell_px=10, margin_px=0, margin_value=255, camera=False):
        """Image of tag ``id`` (uint8, side x side, side = (bits/4 + 1) *
        cell_px + 2 * margin_px): layout white (foam, bright in sonar) is
        255, black (aluminium) 0, the margin margin_value; camera=True
        inverts every pixel (aluminium looks light to a camera)."""
        id = self._tag_id(id)
        cell_px = as_int("cell_px", cell_px, 1, _core.MAX_DIM)
        margin_px = as_int("margin_px", margin_px, 0, _core.MAX_DIM)
        margin_value = as_int("margin_value", margin_value, 0, 255)
        camera = as_bool("camera", camera)
        side = (self.bits // 4 + 1) * cell_px + 2 * margin_px
        if side > _core.MAX_DIM:
            raise ValueError("cell_px {} and margin_px {} make an image of side {} pixels, above "
                             "{}".format(cell_px, margin_px, side, _core.MAX_DIM))
        data, side = self._render(id, cell_px, margin_px, margin_value, camera)
        return array2d(data, side, side)

    def layout(self, id):
        """The (k+1) x (k+1) cell grid of tag ``id`` as rows of 0/1 (1 =
        white / foam), row-major, as printed (k = bits/4)."""
        id = self._tag_id(id)
        k = self.bits // 4
        return [[self.layout_cell(id, x, y) for x in range(k + 1)] for y in range(k + 1)]

    def layout_cell(self, id, x, y):
        """Layout value of grid cell (x, y), 0 <= x, y <= bits/4, of tag
        ``id``: 1 white (foam) or 0 black (aluminium), as printed."""
        k = self.bits // 4
        return super().layout_cell(self._tag_id(id), as_int("x", x, 0, k), as_int("y", y, 0, k))

    def corner_tabs(self, id):
        """OR of ``pyactag.CORNER_*`` bits: the face-plate corners of tag
        ``id`` that need a small metal tab."""
        return super().corner_tabs(self._tag_id(id))


def code_rot90(code, bits):
    """The code of the tag turned 90 degrees counter-clockwise."""
    return _core.code_rot90(code, bits)


def code_reverse(code, bits):
    """The code with its bit order reversed (the published mirror rule)."""
    return _core.code_reverse(code, bits)


def code_mirror(code, bits):
    """The physical reflection a sonar shows (sequence position s -> -s mod bits)."""
    return _core.code_mirror(code, bits)
