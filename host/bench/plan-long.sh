#!/usr/bin/env bash
# ger's planned time against GRBL's for the corpus programs that
# `cargo test --test plan` leaves out as too long for every test run: those
# over its 5000 lines or 60 s, up to GER_PLAN_MOST_LINES lines (default
# 100000) and GER_PLAN_MOST_SECONDS of machine time (default 3600). gtime
# simulates every step, so this takes a while (hours for the longest).
# Writes tests/corpus/PLAN-LONG.md, to review with `git diff`; with
# GER_PLAN_LEAST_SECONDS set, only the programs that take longer than it,
# into tests/corpus/PLAN-LONG-<least>s.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
export GER_PLAN_MOST_LINES="${GER_PLAN_MOST_LINES:-100000}"
export GER_PLAN_MOST_SECONDS="${GER_PLAN_MOST_SECONDS:-3600}"
UPDATE_EXPECT=1 cargo test --quiet --manifest-path "$root/Cargo.toml" --test plan -- --nocapture
