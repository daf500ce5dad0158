#!/usr/bin/env bash
# Builds the fuzz targets on stable Rust and runs each over its seeds and a
# bounded number of inputs (FUZZ_RUNS, default 10000); fails on any panic,
# timeout (10 s for one input) or memory over 1 GiB, leaving the input that
# did it in host/fuzz/artifacts/.
#
#   host/fuzz/run.sh                          every target, bounded (what CI runs)
#   host/fuzz/run.sh translate -runs=-1       one target, until stopped (any libFuzzer flags)
#
# What a target finds that covers something new is kept in
# host/fuzz/corpus/TARGET/ (not committed) and used again by the next run.
set -euo pipefail
fuzz="$(cd "$(dirname "$0")" && pwd)"
targets=(lex parse translate config view_request)
if [ $# -gt 0 ] && [[ $1 != -* ]]; then
  targets=("$1")
  shift
fi

# The coverage instrumentation cargo-fuzz asks for, all stable flags (no
# sanitizer: that part is nightly). An explicit --target keeps RUSTFLAGS off
# build scripts and proc macros, which run in cargo without libFuzzer.
host="$(rustc -vV | sed -n 's/^host: //p')"
coverage=(-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4
  -Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table
  -Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing)
export RUSTFLAGS="${RUSTFLAGS:-} ${coverage[*]}"
export CARGO_TARGET_DIR="$fuzz/target"
cargo build --manifest-path "$fuzz/Cargo.toml" --locked --release --bins --target "$host"
bin="$CARGO_TARGET_DIR/$host/release"
"$fuzz/seeds.sh"

for target in "${targets[@]}"; do
  case "$target" in
  lex | parse | translate) seeds=gcode ;;
  config | view_request) seeds="$target" ;;
  *)
    echo "run.sh: no target $target (there are lex, parse, translate, config, view_request)" >&2
    exit 2
    ;;
  esac
  mkdir -p "$fuzz/corpus/$target" "$fuzz/artifacts"
  echo "== fuzz: $target"
  log="$fuzz/artifacts/$target.log"
  # -max_len: real programs are up to megabytes; mutating a 64 KiB prefix finds as much, faster.
  set +e
  "$bin/$target" -runs="${FUZZ_RUNS:-10000}" -seed=1 -timeout=10 -rss_limit_mb=1024 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$fuzz/artifacts/$target-" "$@" \
    "$fuzz/corpus/$target" "$fuzz/corpus/seeds/$seeds" 2>&1 | tee "$log" |
    grep -E --line-buffered '^(stat::|Done|INFO: seed corpus|#[0-9]+[[:space:]]+(pulse|INITED|DONE))'
  status="${PIPESTATUS[0]}"
  set -e
  if [ "$status" != 0 ]; then
    tail -n 60 "$log"
    echo "run.sh: $target failed (status $status); the input is in host/fuzz/artifacts/, the log in $log" >&2
    exit 1
  fi
done
