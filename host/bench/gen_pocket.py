#!/usr/bin/env python3
"""Writes a 2.5D pocketing program like a CAM post's: a 90 x 90 mm pocket
with 10 mm corner radii, 6 mm endmill, cleared in 1 mm steps to 6 mm deep by
zig-zag passes 2 mm apart, each level entered by a helix and finished by a
contour of lines and corner arcs. In millimetres.

    gen_pocket.py > pocket.ngc
"""


def main() -> None:
    out = []
    w = out.append
    w("(2.5D pocket: 90 x 90 mm, corner radius 10, 6 mm endmill)")
    w("G21 G17 G90")
    w("M06 T1")
    w("M03 S12000")
    w("G00 Z5.000")
    lo, hi, r, tool = 5.0, 95.0, 10.0, 3.0
    for level in range(1, 7):
        z = -float(level)
        # Helix down at the pocket's centre.
        w("G00 X54.000 Y50.000")
        w(f"G01 Z{z + 1:.3f} F600")
        w(f"G03 X54.000 Y50.000 I-4.000 J0.000 Z{z:.3f} F400")
        # Zig-zag clearing, inside the contour by the tool's radius.
        a, b = lo + tool, hi - tool
        c = r - tool

        def inset(y: float) -> float:
            # How far the rounded contour's side is in from the square's at row y.
            d = max(0.0, c - min(y - a, b - y) + 1.0)
            return c - (c * c - min(d, c) ** 2) ** 0.5

        y, row = a + 1.0, 0
        w(f"G01 X{a + 1 + inset(y):.3f} Y{y:.3f} F1200")
        while y <= b - 1.0:
            x = b - 1.0 - inset(y) if row % 2 == 0 else a + 1.0 + inset(y)
            w(f"G01 X{x:.3f}")
            y += 2.0
            if y <= b - 1.0:
                w(f"G01 X{(b - 1.0 - inset(y)) if row % 2 == 0 else (a + 1.0 + inset(y)):.3f} Y{y:.3f}")
            row += 1
        # Finishing contour: lines and quarter arcs (corner radius less the tool's).
        w(f"G01 X{a + c:.3f} Y{a:.3f}")
        w(f"G01 X{b - c:.3f}")
        w(f"G03 X{b:.3f} Y{a + c:.3f} I0.000 J{c:.3f}")
        w(f"G01 Y{b - c:.3f}")
        w(f"G03 X{b - c:.3f} Y{b:.3f} I{-c:.3f} J0.000")
        w(f"G01 X{a + c:.3f}")
        w(f"G03 X{a:.3f} Y{b - c:.3f} I0.000 J{-c:.3f}")
        w(f"G01 Y{a + c:.3f}")
        w(f"G03 X{a + c:.3f} Y{a:.3f} I{c:.3f} J0.000")
        w("G00 Z5.000")
    w("M05")
    w("M30")
    print("\n".join(out))


if __name__ == "__main__":
    main()
