#!/usr/bin/env bash
# Makes the fuzz targets' seed corpus in host/fuzz/corpus/seeds/ (not
# committed): G-code from tests/**/*.ngc and ../shared/corpus (the files its
# INDEX.tsv calls gcode), configs from tests/**/*.toml, and the hand-made
# seeds in host/fuzz/seeds/. Each file is named by its path, `/` as `__`.
set -euo pipefail
fuzz="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$fuzz/../.." && pwd)"
seeds="$fuzz/corpus/seeds"
rm -rf "$seeds"
mkdir -p "$seeds/gcode" "$seeds/config" "$seeds/view_request"

# Copies each file named on standard input (relative to $1) into folder $2.
copy() {
  local from="$1" into="$2" file
  while IFS= read -r file; do
    cp "$from/$file" "$into/${file//\//__}"
  done
}

(cd "$repo" && find tests -name '*.ngc' -not -path '*/node_modules/*') | copy "$repo" "$seeds/gcode"
(cd "$repo" && find tests -name '*.toml' -not -name Cargo.toml -not -path '*/target/*') | copy "$repo" "$seeds/config"
for kind in config view_request; do
  (cd "$fuzz/seeds/$kind" && find . -type f -printf '%P\n') | copy "$fuzz/seeds/$kind" "$seeds/$kind"
done

shared="$repo/../shared/corpus"
if [ -f "$shared/INDEX.tsv" ]; then
  # Columns: path ... file_type (the last); the first line names them.
  awk -F'\t' 'NR > 1 && $NF == "gcode" { print $1 }' "$shared/INDEX.tsv" | copy "$shared" "$seeds/gcode"
elif [ -n "${CI:-}" ]; then
  echo "seeds.sh: $shared/INDEX.tsv is missing; CI must have ../shared/corpus beside the repository" >&2
  exit 1
else
  echo "*** seeds.sh: NOT USED: $shared (missing); seeding from tests/ only" >&2
fi
for kind in gcode config view_request; do
  echo "seeds: $kind $(find "$seeds/$kind" -type f | wc -l) files"
done
