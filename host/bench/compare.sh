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
source host/bench/best_of_three.sh
source host/bench/camotics.sh
out=host/bench/out
mkdir -p "$out"
cargo build --release -q -p ger
ger=$PWD/target/release/ger
corpus=../shared/corpus/camotics-examples
[ -d "$corpus" ] || corpus=/work/shared/corpus/camotics-examples
[ -d "$corpus" ] || { echo "no CAMotics examples found: cannot run"; exit 1; }
camotics_job "$out" "$corpus" cameo ballmill 2 "-83.6,-104.153,-7" "83.6,103.747,0"
"$ger" render "$out/cameo.ngc" --config "$out/cameo.toml" -o "$out/cameo.stl" --resolution 0.46 --quiet
# The comparison finds gouges and material left: its exit status is 1.
best=$(best_of_three "$out" "$ger" compare "$out/cameo.ngc" "$out/cameo.stl" \
  --config "$out/cameo.toml" --resolution 0.1 --tolerance 0.5 --quiet) || true
"$ger" compare "$out/cameo.ngc" "$out/cameo.stl" --config "$out/cameo.toml" --resolution 0.1 --tolerance 0.5 --quiet || true
awk -v r="$best" 'BEGIN { split(r, f, " "); printf "cameo compare at 0.1 mm: %.2f s wall %.2f s cpu %.1f MB peak\n", f[1], f[2] + f[3], f[4] / 1024 }'
