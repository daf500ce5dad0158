#!/usr/bin/env bash
# Benchmark: the interpreter stage flattening a parametric program: three
# nested LinuxCNC while loops (100 x 100 x 100) making 1,000,000 moves, and
# the same moves as Fanuc macro B WHILE ... DO loops. Best of three runs by
# CPU time: wall and CPU seconds, moves per CPU second and peak memory
# (flat memory: the same with 10 x 100 x 100 moves).
#
#   host/bench/macros.sh [OUTER]     (default 100: OUTER x 100 x 100 moves)
set -euo pipefail
cd "$(dirname "$0")/../.."
outer=${1:-100}
out=host/bench/out
mkdir -p "$out"
cargo build --release -q -p ger
ger=target/release/ger
linuxcnc() { # OUTER: the O-word program
  cat <<NGC
G21 G90 G17 F1000
#1 = 0
o100 while [#1 LT $1]
  #2 = 0
  o101 while [#2 LT 100]
    #3 = 0
    o102 while [#3 LT 100]
      G01 X[#3 * 0.5] Y[#2 * 0.5] Z[-0.01 * #1]
      #3 = [#3 + 1]
    o102 endwhile
    #2 = [#2 + 1]
  o101 endwhile
  #1 = [#1 + 1]
o100 endwhile
M30
NGC
}
fanuc() { # OUTER: the macro B program
  cat <<NGC
G21 G90 G17 F1000
#1 = 0
WHILE [#1 LT $1] DO1
#2 = 0
WHILE [#2 LT 100] DO2
#3 = 0
WHILE [#3 LT 100] DO3
G01 X[#3 * 0.5] Y[#2 * 0.5] Z[-0.01 * #1]
#3 = #3 + 1
END3
#2 = #2 + 1
END2
#1 = #1 + 1
END1
M30
NGC
}
# The outer loop makes every move: let it, as a real program would say in ger.toml.
printf '[machine]\nmax_iterations = 100000000\n' > "$out/macros.toml"
source host/bench/best_of_three.sh
measure() { # NAME MOVES FILE
  local best
  best=$(best_of_three "$out" "$ger" run --lenient --units mm --config "$out/macros.toml" "$3" -o "$out/macros.out.ngc") ||
    { cat "$out/stderr"; return 1; }
  report "$1" 34 "$best" "$2" moves
}
for kind in linuxcnc fanuc; do
  for n in 10 "$outer"; do
    "$kind" "$n" > "$out/macros-$kind-$n.ngc"
    measure "$kind, $n x 100 x 100 moves" $((n * 10000)) "$out/macros-$kind-$n.ngc"
  done
done
