#!/usr/bin/env bash
# Benchmark: `ger check` against `ger render` (2D PNG, default resolution) on
# the same 1,000,000-line surfacing program and machine, best of three runs by
# wall time. The issue's target: check within 2x of render.
#   1. with [stock] size given (one pass over the program each);
#   2. without (each first finds the stock in a pass of its own).
#
#   host/bench/check.sh [LINES]     (default 1000000)
set -euo pipefail
cd "$(dirname "$0")/../.."
lines=${1:-1000000}
out=host/bench/out
mkdir -p "$out"
surface="$out/surface-$lines.ngc"
[ -f "$surface" ] || python3 host/bench/gen_surface.py "$lines" > "$surface"
cargo build --release -q -p ger
ger=$PWD/target/release/ger
best_wall() { # COMMAND... : best wall seconds of 3, and its CPU seconds and peak MB
  local best="" line
  for _ in 1 2 3; do
    /usr/bin/time -o "$out/time" -f "%e %U %S %M" "$@" > /dev/null 2> "$out/stderr" || true
    line=$(tail -1 "$out/time")
    if [ -z "$best" ] || awk -v a="$line" -v b="$best" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !(x[1] < y[1]) }'; then
      best=$line
    fi
  done
  echo "$best"
}
report() { # NAME RENDER CHECK
  awk -v n="$1" -v r="$2" -v c="$3" 'BEGIN { split(r, a, " "); split(c, b, " ");
    printf "%-22s render %6.2f s wall %6.2f s cpu %6.1f MB | check %6.2f s wall %6.2f s cpu %6.1f MB | check/render %.2f\n",
      n, a[1], a[2] + a[3], a[4] / 1024, b[1], b[2] + b[3], b[4] / 1024, b[1] / (a[1] > 0 ? a[1] : 0.01) }'
}
echo "$lines-line surfacing program on $(nproc) cores"
for stock in sized margin; do
  cat > "$out/check-$stock.toml" <<'TOML'
units = "mm"
[[tools]]
number = 1
kind = "ballmill"
diameter = 1.0
TOML
  [ "$stock" = sized ] && printf '[stock]\nsize = [100, 100, 12]\norigin = [0, 0, 12]\n' >> "$out/check-$stock.toml"
  render=$(best_wall "$ger" render "$surface" --config "$out/check-$stock.toml" -o "$out/check.png" --quiet)
  check=$(best_wall "$ger" check "$surface" --config "$out/check-$stock.toml" --quiet --allow spindle-off)
  report "stock $stock" "$render" "$check"
done
