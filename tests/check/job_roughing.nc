(Roughing: a slot along Y20 from X20 to X40, 4.5 mm deep in two passes; job.ngc finishes it.)
G21
M03 S10000
G00 X20 Y20 Z1
G01 Z-2 F200
X40
Z-4.5
X20
G00 Z5
M05
M30
