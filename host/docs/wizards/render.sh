#!/usr/bin/env bash
# The README's picture of each wizard: `ger render --view iso` of its
# example in host/examples/wizards/. Run from anywhere; needs a built ger
# (GER=path, default: cargo run --release).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
ger=(${GER:-cargo run --quiet --release --manifest-path "$root/Cargo.toml" --})
for program in "$root"/host/examples/wizards/*.ngc; do
  name="$(basename "$program" .ngc)"
  "${ger[@]}" render "$program" --wizards "$root/wizards" --view iso --size 320x200 \
    -o "$root/host/docs/wizards/$name.png"
done
