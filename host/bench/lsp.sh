#!/usr/bin/env bash
# Benchmark: `ger lsp` on the 1,000,000-line surfacing program: the time from
# an edit (an incremental didChange of one line) to the diagnostics of the
# edited text, beside `ger check` on the same file (the issue's target: the
# editor's diagnostics within the time `ger check` takes), and the latency of
# hovers asked every 20 ms while the analysis runs (the target: an edit never
# blocks a request).
#
#   host/bench/lsp.sh [LINES]     (default 1000000)
set -euo pipefail
cd "$(dirname "$0")/../.."
lines=${1:-1000000}
out=host/bench/out
mkdir -p "$out/lsp"
program="$out/lsp/surface-$lines.ngc"
[ -f "$program" ] || python3 host/bench/gen_surface.py "$lines" > "$program"
cargo build --release -q -p ger
ger=$PWD/target/release/ger
echo "$lines-line surfacing program ($(du -h "$program" | cut -f1)) on $(nproc) cores"
/usr/bin/time -o "$out/lsp/time" -f "%e" "$ger" check -q "$program" > /dev/null 2>&1 || true
echo "ger check: $(cat "$out/lsp/time") s"
python3 host/bench/lsp_client.py "$ger" "$program"
