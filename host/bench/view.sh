#!/usr/bin/env bash
# Benchmark: `ger view`'s live update on a 10,000-line and a 1,000,000-line
# surfacing program (no [stock] size, so each snapshot is two translations:
# the stock's bounds, then translation, check and simulation together).
# Measured, best of three edits: from POST /api/source (the page's edit) to
# the `snapshot` event, then to the state, heights and path fetched as the
# page does; and the server's own `elapsed_ms`.
#
#   host/bench/view.sh [LINES...]     (default 10000 1000000)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=host/bench/out
mkdir -p "$out"
cargo build --release -q -p ger
ger=${CARGO_TARGET_DIR:-$PWD/target}/release/ger
cat > "$out/view.toml" <<'TOML'
units = "mm"
[[tools]]
number = 1
kind = "ballmill"
diameter = 1.0
TOML
now() { date +%s.%N; }
pids=()
trap 'kill "${pids[@]}" 2> /dev/null || true' EXIT
echo "ger view on $(nproc) cores; seconds, best of 3"
[ $# -gt 0 ] || set -- 10000 1000000
for lines in "$@"; do
  program="$out/surface-$lines.ngc"
  [ -f "$program" ] || python3 host/bench/gen_surface.py "$lines" > "$program"
  "$ger" view "$program" --config "$out/view.toml" --port 0 > "$out/view-address" &
  pids+=($!)
  until grep -q '^ger view: ' "$out/view-address"; do sleep 0.05; done
  url=$(sed -n 's|^ger view: \(http://[^/]*\)/$|\1|p' "$out/view-address")
  curl -sN "$url/api/events" > "$out/view-events" &
  pids+=($!)
  ready() { grep -A1 '^event: snapshot' "$out/view-events" | grep -q "^data: {\"version\":$1}"; }
  until ready 1; do sleep 0.01; done
  best_ready="" best_fetched="" best_server=""
  for run in 1 2 3; do
    { cat "$program"; echo "(edit $run)"; } > "$out/view-edit.ngc"
    start=$(now)
    version=$(curl -sf --data-binary @"$out/view-edit.ngc" "$url/api/source" | tr -dc 0-9)
    until ready "$version"; do sleep 0.005; done
    made=$(now)
    curl -sf "$url/api/state" -o "$out/view-state.json"
    curl -sf "$url/api/heights?version=$version" -o /dev/null
    curl -sf "$url/api/path?version=$version" -o /dev/null
    fetched=$(now)
    server=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["elapsed_ms"] / 1000)' "$out/view-state.json")
    pieces=$(python3 -c 'import json, sys; p = json.load(open(sys.argv[1]))["path"]; print(p["pieces"], "of", p["total"])' "$out/view-state.json")
    ready_s=$(echo "$made - $start" | bc)
    fetched_s=$(echo "$fetched - $start" | bc)
    if [ -z "$best_ready" ] || [ "$(echo "$ready_s < $best_ready" | bc)" = 1 ]; then
      best_ready=$ready_s best_fetched=$fetched_s best_server=$server
    fi
  done
  printf '%9d lines: edit to snapshot %7.3f s (server %7.3f s), with state, heights and path fetched %7.3f s; %s pieces drawn, %d MB state\n' \
    "$lines" "$best_ready" "$best_server" "$best_fetched" "$pieces" "$(($(stat -c %s "$out/view-state.json") >> 20))"
  kill "${pids[@]}" 2> /dev/null || true
  pids=()
done
