#!/usr/bin/env bash
# Benchmark: the simulation's cliffs, `ger check` and `ger render` (2D PNG,
# default resolution: 1000 x 1000 cells) on a 4 x 4 x 2 mm stock under a 6 mm
# endmill, every move sweeping the whole stock. Best of three by CPU time.
#   1. repeat: 2000 plunges to Z-1 at one spot, each with its G00 retract;
#   2. jiggle: 2000 moves of 0.01 mm back and forth at Z-1;
#   3. peck: 2000 plunges each deeper than the last (every one lowers every
#      cell: the cost the cells really cut set);
# each with [stock] size given and with the stock found from the program.
#
#   host/bench/cliffs.sh [MOVES]     (default 2000; GER=path times another build)
set -euo pipefail
cd "$(dirname "$0")/../.."
n=${1:-2000}
out=host/bench/out
mkdir -p "$out"
if [ -z "${GER:-}" ]; then cargo build --release -q -p ger; fi
ger=${GER:-$PWD/target/release/ger}
best_cpu() { # NAME COMMAND... : best CPU seconds of 3, with its wall seconds and peak MB
  local name=$1 best="" line
  shift
  for _ in 1 2 3; do
    /usr/bin/time -o "$out/time" -f "%e %U %S %M" "$@" > /dev/null 2> "$out/stderr" || true
    line=$(tail -1 "$out/time")
    if [ -z "$best" ] || awk -v a="$line" -v b="$best" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !(x[2] + x[3] < y[2] + y[3]) }'; then
      best=$line
    fi
  done
  awk -v n="$name" -v r="$best" 'BEGIN { split(r, f, " ");
    printf "%-24s %6.2f s wall %6.2f s cpu %6.1f MB peak\n", n, f[1], f[2] + f[3], f[4] / 1024 }'
}
for kind in repeat jiggle peck; do
  python3 - "$kind" "$n" > "$out/cliff-$kind.ngc" <<'PY'
import sys
kind, n = sys.argv[1], int(sys.argv[2])
print("G21 G90 G17\nM06 T1\nM03 S10000\nG00 Z2\nG00 X2 Y2\nF300")
for k in range(n):
    if kind == "repeat":
        print("G01 Z-1\nG00 Z1")
    elif kind == "jiggle":
        print(f"G01 X{2 + 0.01 * (k % 2):.2f} Z-1")
    else:
        print(f"G01 Z{-1.5 * (k + 1) / n:.5f}\nG00 Z1")
print("G00 Z5\nM05\nM30")
PY
done
printf 'units = "mm"\n[[tools]]\nnumber = 1\nkind = "endmill"\ndiameter = 6.0\n' > "$out/cliff-margin.toml"
cp "$out/cliff-margin.toml" "$out/cliff-sized.toml"
printf '[stock]\nsize = [4, 4, 2]\norigin = [0, 0, 2]\n' >> "$out/cliff-sized.toml"
echo "$n moves at one spot on $(nproc) cores"
for kind in repeat jiggle peck; do
  for stock in sized margin; do
    best_cpu "$kind, $stock, check" "$ger" check "$out/cliff-$kind.ngc" --config "$out/cliff-$stock.toml" --quiet
    best_cpu "$kind, $stock, render" "$ger" render "$out/cliff-$kind.ngc" --config "$out/cliff-$stock.toml" -o "$out/cliff.png" --quiet
  done
done
