# Sourced by the bench scripts that time a command by its CPU time.
#
# best_of_three OUT COMMAND... : runs COMMAND three times under /usr/bin/time
# (its output discarded, its stderr kept in OUT/stderr) and prints the run
# with the least CPU time as "wall user system peak-KB". Fails if a run did.
best_of_three() {
  local out=$1 best="" line failed=0
  shift
  for _ in 1 2 3; do
    /usr/bin/time -o "$out/time" -f "%e %U %S %M" "$@" > /dev/null 2> "$out/stderr" || failed=1
    line=$(tail -1 "$out/time")
    if [ -z "$best" ] || awk -v a="$line" -v b="$best" 'BEGIN { split(a, x, " "); split(b, y, " "); exit !(x[2] + x[3] < y[2] + y[3]) }'; then
      best=$line
    fi
  done
  echo "$best"
  return "$failed"
}

# report NAME WIDTH RUN COUNT UNIT : a run of best_of_three as a line: wall
# and CPU seconds, COUNT UNIT per CPU second, peak memory.
report() {
  awk -v n="$1" -v w="$2" -v r="$3" -v c="$4" -v u="$5" 'BEGIN {
    split(r, f, " "); cpu = f[2] + f[3]; if (cpu <= 0) cpu = 0.01
    printf "%-*s %6.2f s wall %6.2f s cpu  %10.0f %s/s (cpu)  %6.1f MB peak\n", w, n, f[1], cpu, c / cpu, u, f[4] / 1024 }'
}
