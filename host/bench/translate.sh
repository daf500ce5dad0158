#!/usr/bin/env bash
# Benchmark: ger translating a generated 3D-surfacing program (with no config,
# so its tool comments are read first; then with the tools given, so they are
# not), beside LinuxCNC's rs274 on the same file where it is installed.
# Reports the best of three runs: wall and CPU time, lines per CPU second and
# peak memory (CPU time is steadier than wall time on a shared machine).
#
#   host/bench/translate.sh [LINES]     (default 1000000)
set -euo pipefail
cd "$(dirname "$0")/../.."
lines=${1:-1000000}
out=host/bench/out
mkdir -p "$out"
program="$out/surface-$lines.ngc"
[ -f "$program" ] || python3 host/bench/gen_surface.py "$lines" > "$program"
cargo build --release -q -p ger
ger=target/release/ger
source host/bench/best_of_three.sh
measure() { # NAME COMMAND...
  local name=$1; shift
  local best
  # rs274 may end with a status of its own: its time counts all the same.
  best=$(best_of_three "$out" "$@") || true
  report "$name" 22 "$best" "$lines" lines
}
echo "$lines-line surfacing program ($(du -h "$program" | cut -f1)) on $(nproc) cores"
measure "ger run" "$ger" run "$program" -o "$out/surface.out.ngc"
# With the tools and stock in the config, ger does not read the program's tool comments first.
given="$out/tools-given.toml"
printf '[[tools]]\nnumber = 1\nkind = "ballmill"\ndiameter = 0.04\n\n[stock]\nsize = [4, 4, 1]\norigin = [0, 0, 1]\n' > "$given"
measure "ger run, tools given" "$ger" run --config "$given" "$program" -o "$out/surface.out.ngc"

if command -v rs274 >/dev/null; then
  measure "rs274 -g" rs274 -g "$program"
else
  echo "rs274 not installed (Debian: linuxcnc-uspace): no comparison"
fi
