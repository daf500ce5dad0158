#!/usr/bin/env bash
# Benchmark: `ger lsp` on the 1,000,000-line surfacing program: the time from
# the last of ten edits (incremental didChanges of one line, 300 ms apart)
# to the diagnostics of the edited text, beside `ger check` on the same file
# (the issue's target: the editor's diagnostics within the time `ger check`
# takes), and the latency of hovers asked every 20 ms while the edits come
# and the analysis runs (the target: an edit never blocks a request).
#
#   host/bench/lsp.sh [LINES]     (default 1000000)
#   GER=path/to/ger host/bench/lsp.sh   (another build, e.g. an older one to compare)
set -euo pipefail
cd "$(dirname "$0")/../.."
lines=${1:-1000000}
out=host/bench/out
mkdir -p "$out/lsp"
program="$out/lsp/surface-$lines.ngc"
[ -f "$program" ] || python3 host/bench/gen_surface.py "$lines" > "$program"
if [ -z "${GER:-}" ]; then
  cargo build --release -q -p ger
fi
ger=${GER:-$PWD/target/release/ger}
echo "$lines-line surfacing program ($(du -h "$program" | cut -f1)) on $(nproc) cores"
/usr/bin/time -o "$out/lsp/time" -f "%e" "$ger" check -q "$program" > /dev/null 2>&1 || true
echo "ger check: $(cat "$out/lsp/time") s"
python3 host/bench/lsp_client.py "$ger" "$program"
