#!/usr/bin/env bash
# Benchmark: what cutter radius compensation costs. ger translates the same
# long contouring program twice, once as it is and once wrapped in G41 ... G40
# so that every move is compensated, and the times are compared. The budget:
# compensation adds at most 20 % to the translation time.
#
# The program is a CAM-style contour: lap after lap round a 1000-sided polygon
# (radius 40 mm, 6 mm endmill inside it, so every vertex is an inside corner
# the pass cuts), as G01 X Y Z moves in millimetres.
#
#   host/bench/cutter_comp.sh [LINES]     (default 1000000)
#
# Time on a shared machine is noisy; with INSTRUCTIONS=1 the script also
# counts the instructions each run executes (valgrind --tool=callgrind, about
# 50 times slower: use fewer LINES), a figure that does not depend on load.
set -euo pipefail
cd "$(dirname "$0")/../.."
lines=${1:-1000000}
out=host/bench/out
mkdir -p "$out"
plain="$out/contour-$lines.ngc"
comp="$out/contour-$lines-g41.ngc"
config="$out/contour.toml"

printf 'units = "mm"\n[[tools]]\nnumber = 1\nkind = "endmill"\ndiameter = 6.0\n' > "$config"
if [ ! -f "$plain" ] || [ ! -f "$comp" ]; then
  python3 - "$lines" "$plain" "$comp" <<'EOF'
import math
import sys

lines, plain, comp = int(sys.argv[1]), sys.argv[2], sys.argv[3]
sides = 1000
header = [
    "(contour: laps round a 1000-sided polygon, radius 40 mm about X50 Y50)",
    "G21 G17 G90",
    "M06 T1",
    "M03 S12000",
    "G00 Z5.000",
    "G00 X100.000 Y50.000",
    "G01 Z0.000 F800",
]
footer = ["G01 X100.000 Y50.000", "G00 Z5.000", "M05", "M30"]
# The two files have the same lines; where one says G41 or G40 the other has a comment.
moves = lines - len(header) - len(footer) - 2
body = ["G01 X90.000 Y50.000"]
for i in range(1, moves):
    a = 2 * math.pi * (i % sides) / sides
    z = -1.0 - 0.5 * math.sin(3 * a)
    body.append(f"X{50 + 40 * math.cos(a):.3f} Y{50 + 40 * math.sin(a):.3f} Z{z:.3f}")
for path, on, off in [(plain, "(comp off)", "(comp off)"), (comp, "G41", "G40")]:
    with open(path, "w") as f:
        f.write("\n".join(header + [on] + body + [off] + footer) + "\n")
EOF
fi

cargo build --release -q -p ger
ger=target/release/ger
# Both must translate cleanly, or the comparison means nothing.
for program in "$plain" "$comp"; do
  "$ger" run --config "$config" "$program" -o "$out/contour.out.ngc"
done
echo "$lines-line contour ($(du -h "$plain" | cut -f1)), $(grep -c . "$out/contour.out.ngc") lines out with G41; $(nproc) cores"

# CPU time (user + system) is steadier than wall time on a shared machine.
if command -v hyperfine >/dev/null; then
  hyperfine -N --warmup 1 --runs 10 --export-json "$out/cutter_comp.json" \
    -n "without comp" "$ger run --config $config $plain -o $out/plain.out.ngc" \
    -n "with G41" "$ger run --config $config $comp -o $out/comp.out.ngc"
  read -r a b < <(python3 -c '
import json, sys
plain, comp = json.load(open(sys.argv[1]))["results"]
print(plain["user"] + plain["system"], comp["user"] + comp["system"])' "$out/cutter_comp.json")
else
  best() { # the best CPU time of 5 runs
    local best="" t
    for _ in 1 2 3 4 5; do
      /usr/bin/time -o "$out/time" -f "%U %S" "$@" > /dev/null
      t=$(awk '{ print $1 + $2 }' "$out/time")
      if [ -z "$best" ] || awk -v a="$t" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$t; fi
    done
    echo "$best"
  }
  a=$(best "$ger" run --config "$config" "$plain" -o "$out/plain.out.ngc")
  b=$(best "$ger" run --config "$config" "$comp" -o "$out/comp.out.ngc")
fi
verdict=$(awk -v a="$a" -v b="$b" 'BEGIN {
  printf "cpu %.3f s without, %.3f s with G41: %+.1f %% (budget +20 %%)\n", a, b, 100 * (b / a - 1)
  exit !(b <= 1.2 * a) }') && within=1 || within=0
echo "$verdict"

if [ "${INSTRUCTIONS:-}" = 1 ]; then
  count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | awk '/Collected/ { print $4 }'
  }
  a=$(count "$ger" run --config "$config" "$plain" -o "$out/plain.out.ngc")
  b=$(count "$ger" run --config "$config" "$comp" -o "$out/comp.out.ngc")
  awk -v a="$a" -v b="$b" 'BEGIN { printf "instructions: %d without, %d with G41: %+.1f %%\n", a, b, 100 * (b / a - 1) }'
fi
[ "$within" = 1 ]
