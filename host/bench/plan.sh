#!/usr/bin/env bash
# Benchmark: planning the run time of the generated 3D-surfacing program (the
# one host/bench/translate.sh times) on GRBL's default profile, with
# ger-motion's `plan` example: what `ger check` does for its run time, without
# the simulation. Times, best of three by CPU time, the translation alone
# (`--translate-only`) and the translation with the planner after it: the
# difference is the planner's cost. The issue's target: planned in under 2 s.
#
#   host/bench/plan.sh [LINES]     (default 1000000)
set -euo pipefail
cd "$(dirname "$0")/../.."
lines=${1:-1000000}
out=host/bench/out
mkdir -p "$out"
program="$out/surface-$lines.ngc"
[ -f "$program" ] || python3 host/bench/gen_surface.py "$lines" > "$program"
cargo build --release -q -p ger-motion --example plan
source host/bench/best_of_three.sh
config="$out/plan.toml"
printf 'units = "mm"\n' > "$config"
measure() { # NAME COMMAND...
  local name=$1; shift
  report "$name" 26 "$(best_of_three "$out" "$@")" "$lines" lines
}
echo "$lines-line surfacing program ($(du -h "$program" | cut -f1)) on $(nproc) cores"
plan=target/release/examples/plan
measure "translation alone" "$plan" --translate-only "$program" "$config"
measure "translation and plan" "$plan" "$program" "$config"
echo "planned: $("$plan" "$program" "$config" | cut -f1) s"
