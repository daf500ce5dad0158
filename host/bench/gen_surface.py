#!/usr/bin/env python3
"""Writes a 3D-surfacing program like a CAM post's: a raster of G01 X Y Z
moves over a rippled dome, in millimetres, with the usual header and footer.

    gen_surface.py LINES > surface.ngc
"""
import math
import sys


def main() -> None:
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    header = [
        "(3D surfacing: rippled dome, 100 x 100 mm, 1 mm ball)",
        "G21 G17 G90",
        "M06 T1",
        "M03 S18000",
        "G00 Z5.000",
        "G00 X0.000 Y0.000",
        "G01 Z0.000 F1200",
    ]
    footer = ["G00 Z5.000", "M05", "M30"]
    moves = lines - len(header) - len(footer)
    per_row = 1000
    rows = max(1, moves // per_row)
    out = sys.stdout
    out.write("\n".join(header) + "\n")
    written = 0
    row = 0
    while written < moves:
        y = 100.0 * row / rows
        for i in range(per_row):
            if written == moves:
                break
            t = i / (per_row - 1)
            x = 100.0 * (t if row % 2 == 0 else 1.0 - t)
            r = math.hypot(x - 50.0, y - 50.0)
            z = -10.0 + 9.0 * math.cos(min(r, 50.0) / 50.0 * math.pi / 2) + 0.5 * math.sin(x / 3.0) * math.cos(y / 4.0)
            out.write(f"G01 X{x:.3f} Y{y:.3f} Z{z:.3f}\n" if i == 0 else f"X{x:.3f} Y{y:.3f} Z{z:.3f}\n")
            written += 1
        row += 1
    out.write("\n".join(footer) + "\n")


if __name__ == "__main__":
    main()
