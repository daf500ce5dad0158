#!/usr/bin/env bash
# The fuzz run (host/fuzz/run.sh): libfuzzer-sys compiles libFuzzer, which is
# C++, with the system's compiler. Nothing else: the targets build on stable
# Rust with no cargo-fuzz (see run.sh).
set -euo pipefail
command -v c++ >/dev/null || apt-get install -y -qq g++ >/dev/null
echo "fuzz: $(c++ --version | head -n 1)"
