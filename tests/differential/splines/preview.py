"""The path LinuxCNC's preview (the `gcode` module that AXIS draws with, on the
same interpreter as rs274) makes of a program: one line per move end,
`LINE X Y Z` in machine coordinates and millimetres. Splines come out as
the many straight feeds the preview draws them with. Arcs are not expected.

Usage: python3 preview.py PROGRAM VARFILE
"""

import sys

import gcode


class Canon:
    def __init__(self, parameter_file):
        self.parameter_file = parameter_file
        self.line = 0
        self.g5x = (0.0, 0.0, 0.0)
        self.g92 = (0.0, 0.0, 0.0)

    # What the interpreter asks of the machine: one in inches, as rs274's
    # (whose var file, in inches, this one reads too).
    def get_external_length_units(self):
        return 1 / 25.4

    def get_external_angular_units(self):
        return 1.0

    def get_axis_mask(self):
        return 7

    def get_block_delete(self):
        return 0

    def get_tool(self, number):
        return (number,) + (0.0,) * 12 + (0,)

    def next_line(self, state):
        self.line = state.sequence_number

    # Offsets and moves; the module hands lengths in inches.
    def set_g5x_offset(self, index, x, y, z, *rest):
        self.g5x = (x, y, z)

    def set_g92_offset(self, x, y, z, *rest):
        self.g92 = (x, y, z)

    def move(self, x, y, z):
        machine = [(v + o + p) * 25.4 for v, o, p in zip((x, y, z), self.g5x, self.g92)]
        print(self.line, *("%.9f" % v for v in machine))

    def straight_feed(self, x, y, z, *rest):
        self.move(x, y, z)

    def straight_traverse(self, x, y, z, *rest):
        self.move(x, y, z)

    def arc_feed(self, *args):
        raise RuntimeError("arcs are not expected in the spline programs")

    def __getattr__(self, name):
        # Every other canonical call (spindle, feed, plane, comments) changes no position.
        return lambda *args: None


result, last_line = gcode.parse(sys.argv[1], Canon(sys.argv[2]), "", "")
if result > gcode.MIN_ERROR:
    sys.exit("LinuxCNC's preview refused line %d: %s" % (last_line, gcode.strerror(result)))
