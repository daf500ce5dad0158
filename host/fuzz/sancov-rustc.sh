#!/bin/sh
# RUSTC_WRAPPER for the fuzz build (run.sh): cargo runs it as
# `sancov-rustc.sh RUSTC ARGS...`. Only ger and the fuzz targets get
# libFuzzer's coverage instrumentation (the flags cargo-fuzz passes, all
# stable); every other crate is compiled exactly as `cargo test` compiles it,
# so the fuzz build reuses those in target/ instead of building wasmtime again.
rustc="$1"
shift
case "${CARGO_PKG_NAME:-}" in
ger | ger-fuzz)
  exec "$rustc" "$@" \
    -Cpasses=sancov-module \
    -Cllvm-args=-sanitizer-coverage-level=4 \
    -Cllvm-args=-sanitizer-coverage-inline-8bit-counters \
    -Cllvm-args=-sanitizer-coverage-pc-table \
    -Cllvm-args=-sanitizer-coverage-trace-compares
  ;;
esac
exec "$rustc" "$@"
