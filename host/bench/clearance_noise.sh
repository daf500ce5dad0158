#!/usr/bin/env bash
# How noisy are the collision, clearance and fixture rules on real programs?
# Runs `ger check --lenient --format json` on every 3-axis mill program of the
# shared corpus (../shared/corpus/INDEX.tsv; other machines, the reject suite
# and programs over MAX_LINES lines left out) with the tools the program
# itself describes (its comments, its CAMotics project, else the default
# tool: no ger.toml), and counts the programs each rule fires on, the
# findings, and how many programs had a tool whose shank could be checked
# (a flute length known). The programs that fire are listed in
# host/bench/out/noise.tsv (program, rule, count, first message) to look at,
# with the programs whose shank was checked (their fluted tools, how deep they cut).
#   host/bench/clearance_noise.sh [MAX_LINES]     (default 20000)
set -euo pipefail
cd "$(dirname "$0")/../.."
max_lines=${1:-20000}
out=host/bench/out
mkdir -p "$out"
cargo build --release -q -p ger
ger=$PWD/target/release/ger
corpus=../shared/corpus
[ -d "$corpus" ] || corpus=/work/shared/corpus
[ -f "$corpus/INDEX.tsv" ] || { echo "no corpus index found: cannot run"; exit 1; }
python3 - "$ger" "$corpus" "$max_lines" "$out" <<'PY'
import csv, json, subprocess, sys, collections
ger, corpus, max_lines, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
rules = ["collision", "clearance", "fixture", "rapid-into-stock"]
fired = collections.Counter()
findings = collections.Counter()
checked = shank_known = failed = 0
rows = []
with open(f"{corpus}/INDEX.tsv") as index:
    for e in csv.DictReader(index, delimiter="\t"):
        f = e["features"]
        if (e["file_type"] != "gcode" or "ABC-axes" in f or "printer-M-codes" in f or "plasma" in e["source_repo"]
                or "lathe" in e["path"] or "expected-error" in e["source_repo"] or int(e["lines"] or 0) > max_lines):
            continue
        units = "mm" if e["units"] == "G21" else "in"
        try:
            run = subprocess.run([ger, "check", "--lenient", "--units", units, "--format", "json", "--quiet",
                                  f"{corpus}/{e['path']}"], capture_output=True, text=True, timeout=120)
            report = json.loads(run.stdout)
        except (subprocess.TimeoutExpired, json.JSONDecodeError):
            failed += 1
            continue
        checked += 1
        fluted = [t for t in report["summary"]["tools"] if t.get("flute_length")]
        if fluted:
            shank_known += 1
            tools = ", ".join(f"T{t['number']} {t['diameter']} flutes {t['flute_length']}" for t in fluted)
            cut = report["summary"]["cut_box"]
            depth = cut["max"][2] - cut["min"][2] if cut else 0
            rows.append(f"{e['path']}\tshank checked\t0\t{tools}; cut {depth:.3f} deep")
        by_rule = collections.Counter(d["rule"] for d in report["diagnostics"])
        for rule in rules:
            n = report["summary"]["problems"].get(rule, 0)
            if n:
                fired[rule] += 1
                findings[rule] += n
                first = next(d for d in report["diagnostics"] if d["rule"] == rule)
                rows.append(f"{e['path']}\t{rule}\t{n}\t{first['line']}: {first['message']}")
with open(f"{out}/noise.tsv", "w") as tsv:
    tsv.write("\n".join(rows) + "\n")
print(f"{checked} mill programs checked ({failed} did not finish or give a report), {shank_known} with a flute length known")
for rule in rules:
    print(f"  {rule:17} fires on {fired[rule]:3} programs, {findings[rule]:6} findings")
print(f"the programs that fire: {out}/noise.tsv")
PY
