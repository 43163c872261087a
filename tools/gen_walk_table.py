#!/usr/bin/env python3
"""The walk table k_walk of src/contours.c, from the sweep it replaces.

usage: tools/gen_walk_table.py > table.txt   (the initialiser's body)

One step of Suzuki-Abe border following (steps 3.3 and 3.4) at a pixel
whose 3 x 3 neighbourhood is nb (bit 0 NW, 1 N, 2 NE, 3 W, 4 E, 5 SW, 6 S,
7 SE; 1 = white), entered along an edge of direction din (directions 0 E,
1 NE, 2 N, 3 NW, 4 W, 5 SW, 6 S, 7 SE):
  k_walk[0][din << 8 | nb]: dout, the first white neighbour counterclockwise
      from just after the previous pixel (direction din + 4);
  k_walk[1][dout << 8 | nb]: din, the same step undone (the first white
      neighbour clockwise from just before the next pixel, dout itself
      last: the previous pixel);
bit 3 of either entry: the counterclockwise sweep passed over the east
neighbour. k_walk[1] with a black next pixel is Suzuki-Abe's step 3.1 (bits
0..2 only); entries whose previous pixel (k_walk[0]) or whose only white
neighbour (k_walk[1]) is black never occur; they hold what the formulas
give. tests/test_contour_walk.c checks the table in the source against the
same rule.
"""

# nb bit of the neighbour in each direction
NB_BIT = [4, 2, 1, 0, 3, 5, 6, 7]


def dir_mask(nb):
    return sum(1 << d for d in range(8) if nb >> NB_BIT[d] & 1)


def forward(din, nb):
    m = dir_mask(nb)
    s1 = ((din + 4) & 7) + 1  # the sweep's first direction, 1 .. 8
    for k in range(8):
        if m >> ((s1 + k) & 7) & 1:
            t = s1 + k
            return (t & 7) | (t > 8) << 3
    return ((s1 + 8) & 7) | 1 << 3  # isolated: never looked up


def backward(dout, nb):
    m = dir_mask(nb)
    for k in range(1, 9):
        p = (dout - k) & 7  # the previous pixel's direction
        if m >> p & 1:
            t = p + 1 + ((dout - p - 1) & 7)  # the forward sweep's end
            return ((p + 4) & 7) | (t > 8) << 3
    return 0  # isolated: never looked up


def main():
    for f in (forward, backward):
        tab = [f(d, nb) for d in range(8) for nb in range(256)]
        print("    {")
        for i in range(0, len(tab), 32):
            print("        " + ", ".join(str(v) for v in tab[i:i + 32]) + ",")
        print("    },")


if __name__ == "__main__":
    main()
