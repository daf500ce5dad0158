#!/usr/bin/env bash
# Wizards: the tests build Rust, Python and JavaScript wizards through
# `ger wizard build`'s own code, which installs componentize-py (pip, into a
# venv) and esbuild and jco (npm) under each wizards directory's target/. What that code
# cannot install itself is checked here: the wasm32-wasip2 Rust target
# (ger adds it with rustup, done here once so a failure shows early),
# python3 with venv, and node with npm.
set -euo pipefail
rustup target add wasm32-wasip2 >/dev/null 2>&1 || rustup target list --installed | grep -qx wasm32-wasip2
python3 -c 'import venv' || apt-get install -y -qq python3-venv >/dev/null
command -v npm >/dev/null || apt-get install -y -qq nodejs npm >/dev/null
echo "wizards: wasm32-wasip2 ready; $(python3 --version); node $(node --version)"
