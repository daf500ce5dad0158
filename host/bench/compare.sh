#!/usr/bin/env bash
# Benchmark: `ger compare` on CAMotics' cameo (from ../shared/corpus, its
# tool and stock as host/bench/render.sh takes them) against an STL of its
# own simulated part, at a 0.1 mm grid: best of three by CPU time, with the
# wall time and peak memory. The STL is ger's own render at 0.46 mm (at
# 0.1 mm it would be 14 million triangles, 700 MB of STL); the comparison
# samples it on the 0.1 mm grid.
#   host/bench/compare.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
out=host/bench/out
mkdir -p "$out"
cargo build --release -q -p ger
ger=$PWD/target/release/ger
corpus=../shared/corpus/camotics-examples
[ -d "$corpus" ] || corpus=/work/shared/corpus/camotics-examples
[ -d "$corpus" ] || { echo "no CAMotics examples found: cannot run"; exit 1; }
sed -E 's/\bG80\b|\bG64\b|\bG94\b//g; s/T([0-9]+) ?M0?6/M06 T\1/; s/S[0-9.]+//g' "$corpus/cameo/cameo.nc" > "$out/cameo.ngc"
cat > "$out/cameo.toml" <<'TOML'
units = "mm"
[[tools]]
number = 1
kind = "ballmill"
diameter = 2
[stock]
size = [167.2, 207.9, 7]
origin = [83.6, 104.153, 7]
TOML
"$ger" render "$out/cameo.ngc" --config "$out/cameo.toml" -o "$out/cameo.stl" --resolution 0.46 --quiet
best=""
for _ in 1 2 3; do
  /usr/bin/time -o "$out/time" -f "%e %U %S %M" "$ger" compare "$out/cameo.ngc" "$out/cameo.stl" \
    --config "$out/cameo.toml" --resolution 0.1 --tolerance 0.5 --quiet > "$out/compare.txt" || true
  line=$(tail -1 "$out/time")
  if [ -z "$best" ] || awk -v a="$line" -v b="$best" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !(x[2] + x[3] < y[2] + y[3]) }'; then
    best=$line
  fi
done
cat "$out/compare.txt"
awk -v r="$best" 'BEGIN { split(r, f, " "); printf "cameo compare at 0.1 mm: %.2f s wall %.2f s cpu %.1f MB peak\n", f[1], f[2] + f[3], f[4] / 1024 }'
