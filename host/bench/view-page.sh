#!/usr/bin/env bash
# Benchmark: the page of `ger view` in a real headless Chromium (tests/e2e/bench.mjs).
#   1. a 10,000-line surfacing program: from a keystroke in the page, and from
#      the file written on disk, to the page showing the new version (its
#      output pane and 3D view drawn);
#   2. a 1,000,000-line one: from opening the page to its first full draw.
# Needs Chromium and node (see .ci/setup.d/30-chromium.sh).
#
#   host/bench/view-page.sh [SMALL_LINES] [LARGE_LINES]     (default 10000 1000000)
set -euo pipefail
cd "$(dirname "$0")/../.."
small=${1:-10000}
large=${2:-1000000}
out=host/bench/out
mkdir -p "$out"
cargo build --release -q -p ger
ger=${CARGO_TARGET_DIR:-$PWD/target}/release/ger
[ -d tests/e2e/node_modules/playwright-core ] || (cd tests/e2e && npm ci --no-audit --no-fund --loglevel=error)
cat > "$out/ger.toml" <<'TOML'
units = "mm"
[[tools]]
number = 1
kind = "ballmill"
diameter = 1.0
TOML

server=""
trap '[ -n "$server" ] && kill "$server" 2>/dev/null' EXIT
serve() { # PROGRAM: starts ger view on it, sets $server and $url
  "$ger" view "$1" --config "$out/ger.toml" --port 0 > "$out/view.stdout" 2> "$out/view.stderr" &
  server=$!
  for _ in $(seq 300); do
    url=$(head -1 "$out/view.stdout" | sed -n 's/^ger view: //p')
    [ -n "$url" ] && break
    sleep 0.1
  done
  [ -n "$url" ] || { echo "ger view did not start: $(cat "$out/view.stderr")" >&2; exit 1; }
  # Wait for the first snapshot, so the page's times are the page's.
  until curl -sf "${url}api/state" | grep -q '"busy":false'; do sleep 0.2; done
}
stop() { kill "$server"; wait "$server" 2>/dev/null || true; server=""; }

echo "on $(nproc) cores; $(/usr/bin/chromium --version 2>/dev/null)"
for lines in "$small" "$large"; do
  program="$out/view-surface-$lines.ngc"
  python3 host/bench/gen_surface.py "$lines" > "$program"
  serve "$program"
  echo "== $lines lines ($(du -h "$program" | cut -f1))"
  if [ "$lines" = "$small" ]; then
    (cd tests/e2e && node bench.mjs live "$url" "$PWD/../../$program")
  fi
  (cd tests/e2e && node bench.mjs load "$url")
  stop
done
