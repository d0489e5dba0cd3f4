#!/usr/bin/env python3
"""Writes configs/bench/scenes/standing_wave_water.obj: a closed block of water whose top is
the first standing-wave mode of a tank lambda/2 long, y = h + A cos(k x), k = 2 pi / lambda,
over x in [-0.1, 0.6], z in [-0.1, 0.2], bottom at y = -0.1 (the tank, [0, 0.5] in x, cuts it).
Outward-facing triangles. Usage: make_standing_wave_obj.py [OUT.obj] (the defaults below are
those of configs/bench/scenes/standing_wave.json)."""

import math
import sys

DEPTH, AMPLITUDE, WAVELENGTH = 0.25, 0.004, 1.0
X0, X1, Z0, Z1, BOTTOM, SEGMENTS = -0.1, 0.6, -0.1, 0.2, -0.1, 140


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "configs/bench/scenes/standing_wave_water.obj"
    k = 2 * math.pi / WAVELENGTH
    xs = [X0 + (X1 - X0) * i / SEGMENTS for i in range(SEGMENTS + 1)]
    top = [DEPTH + AMPLITUDE * math.cos(k * x) for x in xs]
    v, f = [], []

    def vertex(x, y, z):
        v.append((x, y, z))
        return len(v)  # OBJ indices start at 1

    # Per column i: top-front, top-back, bottom-front, bottom-back.
    cols = [(vertex(x, t, Z0), vertex(x, t, Z1), vertex(x, BOTTOM, Z0), vertex(x, BOTTOM, Z1))
            for x, t in zip(xs, top)]
    for (tf, tb, bf, bb), (tf2, tb2, bf2, bb2) in zip(cols, cols[1:]):
        f += [(tf, tb, tb2), (tf, tb2, tf2)]      # top (+y)
        f += [(bf, bf2, bb2), (bf, bb2, bb)]      # bottom (-y)
        f += [(bf, tf, tf2), (bf, tf2, bf2)]      # front (-z)
        f += [(bb, bb2, tb2), (bb, tb2, tb)]      # back (+z)
    tf, tb, bf, bb = cols[0]
    f += [(bf, bb, tb), (bf, tb, tf)]             # left end (-x)
    tf, tb, bf, bb = cols[-1]
    f += [(bf, tf, tb), (bf, tb, bb)]             # right end (+x)
    with open(out, "w") as obj:
        obj.write(f"# A closed block of water, top y = h + A cos(2 pi x / lambda) (standing wave)\n# h = {DEPTH}, A = {AMPLITUDE}, lambda = "
                  f"{WAVELENGTH}; written by scripts/make_standing_wave_obj.py\n")
        for x, y, z in v:
            obj.write(f"v {x:.9f} {y:.9f} {z:.9f}\n")
        for a, b, c in f:
            obj.write(f"f {a} {b} {c}\n")


if __name__ == "__main__":
    main()
