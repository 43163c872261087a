#!/usr/bin/env python3
"""The sorting networks of src/median_net9.h (the 9 x 9 median, radius 4).

usage: tools/gen_median_net.py > src/median_net9.h

Following Adams (2021, "Fast median filters using separable sorting
networks"), the work of neighbouring windows is shared. Outputs come in
2 x 2 tiles: rows y and y + 1, columns x and x + 1. Every window of the
tile holds the block of rows y-3 .. y+4 by columns x-3 .. x+4 (64
samples); the two rows add row y - 4 or y + 5 across columns x-3 .. x+4;
each output then adds its own column, x - 4 or x + 5, rows y-4 .. y+4 or
y-3 .. y+5.

The block is built from pieces that neighbouring tiles share (columns
counted from c = x - 3, an odd offset from the tile's even x):
  S1(c)  column c's eight core rows, sorted (mn_sort_8: Batcher's
         odd-even merge sort, checked on all 256 0-1 inputs);
  S2(c)  S1(c) merged with S1(c + 1): 16 sorted (mn_merge_8_8);
  S4(c)  S2(c) merged with S2(c + 2): 32 sorted (mn_merge_16_16);
and the tile merges S4(x - 3) with S4(x + 1). Each S2 and S4 serves
several tiles (the tiles 2 columns apart overlap by 6 of their 8 block
columns), so it is computed once per position, not once per tile. The row
above is shared the same way: H2(c) sorts row y - 4's samples at c and
c + 1 (mn_sort_1_1), H4(c) merges H2(c) and H2(c + 2) (mn_merge_2_2); the
tile merges H4(x - 3) and H4(x + 1). Likewise the row below.

mn_tile then works down a tree: the block's merge keeps only the ranks
that can still be the median of a window that adds the 17 samples it lacks
(ranks 23..40 of 64, 0-based); each row adds its 8 and keeps ranks 31..40
of 72; each output adds its 9 (its column's S1 and the one sample of the
extra row) and keeps rank 40 of 81, the median. Merges are Batcher's
odd-even merge (correct for any two lengths; every merge used here is
checked on all its sorted 0-1 inputs, which by the 0-1 principle covers
every input), and a comparator is kept only if an output needs one of its
results; one whose min (or max) alone is needed costs one instruction.

The text is written on macros so that one text serves every vector width:
MN_V (the vector type), MN_MIN, MN_MAX (lane-wise unsigned byte min and
max), MN_LD(p) and MN_ST(p, v) (a vector load and store at byte address
p), MN_ATTR (the functions' attribute), MN_FN(x) (function x's name for
the width: median_net.h is included once per width, two of them in one
x86-64 translation unit; a name that ends in a digit ends in "_", so
that the width reads apart from it). Every list argument is a base
address and a stride: element j of list a is at a + j * sa. The script
checks mn_tile against sorted medians of random windows (values drawn from
small ranges too, so ties are common) before printing anything.
"""
import random
import sys

sys.setrecursionlimit(10000)
R = 4
K = 2 * R + 1
N = K * K
MED = N // 2


class Net:
    """A comparator network in single-assignment form: a comparator reads
    two wires and creates two new ones (its min and its max)."""

    def __init__(self):
        self.cmps = []
        self.nwires = 0

    def wire(self):
        self.nwires += 1
        return self.nwires - 1

    def cx(self, i, j):
        lo, hi = self.wire(), self.wire()
        self.cmps.append((i, j, lo, hi))
        return lo, hi


SIZES = set()  # (len(a), len(b)) of every top-level merge built


def oemerge(net, a, b, top=True):
    """Batcher's odd-even merge of the sorted wire lists a and b."""
    if top and a and b:
        SIZES.add((len(a), len(b)))
    if not a:
        return list(b)
    if not b:
        return list(a)
    if len(a) == 1 and len(b) == 1:
        return list(net.cx(a[0], b[0]))
    v = oemerge(net, a[0::2], b[0::2], False)
    w = oemerge(net, a[1::2], b[1::2], False)
    seq = []
    for k in range(max(len(v), len(w))):
        if k < len(v):
            seq.append(v[k])
        if k < len(w):
            seq.append(w[k])
    for k in range(1, len(seq) - 1, 2):
        seq[k], seq[k + 1] = net.cx(seq[k], seq[k + 1])
    return seq


def apply(cmps, val):
    """The comparators (i, j, lo, hi, ...) in order on the values val (a
    list indexed by wire), in place; returns val."""
    for c in cmps:
        i, j, lo, hi = c[:4]
        val[lo], val[hi] = min(val[i], val[j]), max(val[i], val[j])
    return val


def check_merges(sizes):
    """Each merge of lengths (m, n) on every sorted 0-1 input."""
    for m, n in sorted(sizes):
        net = Net()
        a = [net.wire() for _ in range(m)]
        b = [net.wire() for _ in range(n)]
        out = oemerge(net, a, b, False)
        for za in range(m + 1):
            for zb in range(n + 1):
                val = [0] * (m - za) + [1] * za + [0] * (n - zb) + [1] * zb
                val += [0] * (net.nwires - len(val))
                apply(net.cmps, val)
                o = [val[w] for w in out]
                assert o == sorted(o), (m, n)


def prune(net, outs):
    """The comparators some output needs, in order, with which of their
    two results are needed."""
    need = set(outs)
    kept = []
    for i, j, lo, hi in reversed(net.cmps):
        ni, nj = lo in need, hi in need
        if ni or nj:
            kept.append((i, j, lo, hi, ni, nj))
            need.add(i)
            need.add(j)
    kept.reverse()
    return kept


def schedule(kept, outs):
    """The kept comparators depth first from the outputs, each just before
    its first use (fewer values live at once than in building order)."""
    by_out = {}
    for c in kept:
        by_out[c[2]] = c
        by_out[c[3]] = c
    done = set()
    order = []
    for o in outs:
        stack = [(by_out.get(o), False)]
        while stack:
            c, expanded = stack.pop()
            if c is None or id(c) in done:
                continue
            if expanded:
                done.add(id(c))
                order.append(c)
                continue
            stack.append((c, True))
            for w in (c[1], c[0]):
                stack.append((by_out.get(w), False))
    return order


def run(kept, nwires, inputs):
    """The network on concrete values: inputs maps wire -> value."""
    val = [0] * nwires
    for w, v in inputs.items():
        val[w] = v
    return apply(kept, val)


def build_tile():
    """mn_tile: the lists it reads (name -> wires) and its four outputs
    (row y: x, x + 1; row y + 1: x, x + 1)."""
    net = Net()
    lists = {}
    for name, n in (("a", 32), ("b", 32), ("ta", 4), ("tb", 4), ("ba", 4), ("bb", 4),
                    ("p0", 8), ("p9", 8)):
        lists[name] = [net.wire() for _ in range(n)]
    for name in ("t0", "t9", "b0", "b9"):
        lists[name] = [net.wire()]

    def keep(lst, m, pa):
        """Ranks of a set of m samples that can still be the median of a
        window of N that holds it; lst[0] is the set's rank pa."""
        lo = max(0, MED - (N - m))
        hi = min(m - 1, MED)
        return lst[lo - pa:hi + 1 - pa], lo

    block, pa = keep(oemerge(net, lists["a"], lists["b"]), 64, 0)
    outs = []
    for row in ("t", "b"):
        extra = oemerge(net, lists[row + "a"], lists[row + "b"])
        rowl, pr = keep(oemerge(net, block, extra), 72, pa)
        for col in ("0", "9"):
            own = oemerge(net, lists["p" + col], lists[row + col])
            med, _ = keep(oemerge(net, rowl, own), 81, pr)
            assert len(med) == 1
            outs.append(med[0])
    return net, lists, outs


def check_tile(net, lists, outs, kept, trials=20000):
    """mn_tile against sorted medians of random 10 x 10 source windows."""
    rng = random.Random(12345)
    for t in range(trials):
        top = rng.choice([1, 2, 3, 7, 255])
        s = [[rng.randint(0, top) for _ in range(K + 1)] for _ in range(K + 1)]  # s[row - (y-4)][k]

        def col(k):
            return sorted(s[r][k] for r in range(1, 9))

        v = {}

        def put(name, values):
            for w, x in zip(lists[name], values):
                v[w] = x

        put("a", sorted(col(1) + col(2) + col(3) + col(4)))
        put("b", sorted(col(5) + col(6) + col(7) + col(8)))
        put("ta", sorted(s[0][1:5]))
        put("tb", sorted(s[0][5:9]))
        put("ba", sorted(s[9][1:5]))
        put("bb", sorted(s[9][5:9]))
        put("p0", col(0))
        put("p9", col(9))
        put("t0", [s[0][0]])
        put("t9", [s[0][9]])
        put("b0", [s[9][0]])
        put("b9", [s[9][9]])
        got = run(kept, net.nwires, v)
        for idx, (dy, dx) in enumerate([(0, 0), (0, 1), (1, 0), (1, 1)]):
            win = sorted(s[r][k] for r in range(dy, dy + K) for k in range(dx, dx + K))
            assert got[outs[idx]] == win[MED], (t, dy, dx)


STRIDE = {"a": "sa", "b": "sa", "ta": "st", "tb": "st", "ba": "st", "bb": "st", "p0": "sp",
          "p9": "sp"}


def load_names(lists):
    """The C expression that loads each input wire of mn_tile."""
    name = {}
    for lname, wires in lists.items():
        for j, w in enumerate(wires):
            if len(wires) == 1:
                name[w] = "MN_LD(%s)" % lname
            else:
                name[w] = "MN_LD(%s + %d * %s)" % (lname, j, STRIDE[lname])
    return name


def body(kept, outs, name):
    lines = []
    nv = 0
    for i, j, lo, hi, ni, nj in schedule(kept, outs):
        a, b = name[i], name[j]
        if ni:
            lines.append("    const MN_V v%d = MN_MIN(%s, %s);" % (nv, a, b))
            name[lo] = "v%d" % nv
            nv += 1
        if nj:
            lines.append("    const MN_V v%d = MN_MAX(%s, %s);" % (nv, a, b))
            name[hi] = "v%d" % nv
            nv += 1
    return lines, nv


def emit_merge(m, n, fname):
    """A full merge of sorted lists of m and n at a and b into o."""
    net = Net()
    a = [net.wire() for _ in range(m)]
    b = [net.wire() for _ in range(n)]
    out = oemerge(net, a, b)
    kept = prune(net, out)
    name = {}
    for j, w in enumerate(a):
        name[w] = "MN_LD(a + %d * sa)" % j
    for j, w in enumerate(b):
        name[w] = "MN_LD(b + %d * sb)" % j
    lines, nv = body(kept, out, name)
    head = "MN_ATTR static void MN_FN(%s_)(" % fname
    emit_fn(["/* %s: sorted lists of %d at a and %d at b merged into o (%d min/max) */"
             % (fname, m, n, nv),
             "%sconst uint8_t *a, size_t sa, const uint8_t *b," % head,
             "%s size_t sb, uint8_t *o, size_t so)" % (" " * (len(head) - 1))],
            lines, out, name)
    return nv


def emit_fn(header, lines, out, name):
    """A function: its comment and signature lines, the body's lines, then
    each output stored at o (stride so)."""
    for l in header:
        print(l)
    print("{")
    for l in lines:
        print(l)
    for j, w in enumerate(out):
        print("    MN_ST(o + %d * so, %s);" % (j, name[w]))
    print("}")
    print()


def sort_net(n):
    """Batcher's odd-even merge sort of n wires: the network, its inputs
    and its outputs (ascending)."""
    net = Net()
    ins = [net.wire() for _ in range(n)]
    lists = [[w] for w in ins]
    while len(lists) > 1:
        lists = [oemerge(net, lists[i], lists[i + 1], False) if i + 1 < len(lists)
                 else lists[i] for i in range(0, len(lists), 2)]
    return net, ins, lists[0]


def check_sort(n):
    """The sort of n on every 0-1 input (the 0-1 principle)."""
    net, ins, out = sort_net(n)
    for bits in range(1 << n):
        val = [0] * net.nwires
        for k, w in enumerate(ins):
            val[w] = bits >> k & 1
        apply(net.cmps, val)
        o = [val[w] for w in out]
        assert o == sorted(o), n


def emit_sort(n, fname):
    """A sort of the n lists of one at p (stride sp) into o (stride so)."""
    net, ins, out = sort_net(n)
    kept = prune(net, out)
    name = {w: "MN_LD(p + %d * sp)" % j for j, w in enumerate(ins)}
    lines, nv = body(kept, out, name)
    emit_fn(["/* %s: the %d vectors at p (stride sp) sorted lane-wise into o (%d min/max) */"
             % (fname, n, nv),
             "MN_ATTR static void MN_FN(%s_)(const uint8_t *p, size_t sp, uint8_t *o, size_t so)"
             % fname],
            lines, out, name)
    return nv


# The pieces the driver merges once per position (median_net.h): pairs and
# fours of sorted columns (S2, S4) and of single samples (H2, H4)
PIECES = ((8, 8), (16, 16), (1, 1), (2, 2))


def main():
    net, lists, outs = build_tile()
    kept = prune(net, outs)
    check_merges(SIZES | set(PIECES))
    check_sort(8)
    check_tile(net, lists, outs, kept)

    print("/* median_net9.h -- generated by tools/gen_median_net.py (do not edit):")
    print(" * internal to median_net.h, included once per vector width (no include")
    print(" * guard) after median.c has defined MN_V, MN_MIN, MN_MAX, MN_LD, MN_ST,")
    print(" * MN_ATTR and MN_FN. The 9 x 9 median on 2 x 2 tiles of outputs from")
    print(" * shared sorted pieces; the script says how. */")
    print()
    ops = {"sort 8": emit_sort(8, "mn_sort_8")}
    for m, n in PIECES:
        ops[(m, n)] = emit_merge(m, n, "mn_%s_%d_%d" % ("sort" if m == 1 else "merge", m, n))
    name = load_names(lists)
    lines, nv = body(kept, outs, name)
    print("/* mn_tile: the four medians of a tile (out[0], out[1]: row y, columns x")
    print(" * and x + 1; out[2], out[3]: row y + 1) from S4(x - 3) at a and S4(x + 1)")
    print(" * at b (32 each, stride sa), H4 of the row above at ta, tb and of the row")
    print(" * below at ba, bb (4 each, stride st), the columns x - 4 and x + 5's")
    print(" * S1 at p0, p9 (8 each, stride sp) and their samples of the rows above")
    print(" * (t0, t9) and below (b0, b9): %d min/max. */" % nv)
    print("MN_ATTR static void MN_FN(mn_tile)(const uint8_t *a, const uint8_t *b, size_t sa,")
    print("                                   const uint8_t *ta, const uint8_t *tb, const uint8_t *ba,")
    print("                                   const uint8_t *bb, size_t st, const uint8_t *p0,")
    print("                                   const uint8_t *p9, size_t sp, const uint8_t *t0,")
    print("                                   const uint8_t *t9, const uint8_t *b0, const uint8_t *b9,")
    print("                                   MN_V *out)")
    print("{")
    for l in lines:
        print(l)
    for idx, o in enumerate(outs):
        print("    out[%d] = %s;" % (idx, name[o]))
    print("}")
    sys.stderr.write("mn_tile %d min/max; merges %s\n" % (nv, ops))


if __name__ == "__main__":
    main()
