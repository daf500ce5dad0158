# Sourced by the bench scripts that run CAMotics' examples.
#
# camotics_job OUT CORPUS NAME KIND DIAMETER MIN MAX : writes OUT/NAME.ngc,
# CORPUS/NAME/NAME.nc with what ger's strict dialect does not take removed
# (G80, G64, G94, S words; `T1 M6` written `M06 T1`), and OUT/NAME.toml, a
# mm machine with tool 1 of KIND and DIAMETER and the stock from corner MIN
# to MAX ("x,y,z"), as the example's CAMotics project has them.
camotics_job() {
  local out=$1 corpus=$2 name=$3 kind=$4 diameter=$5 min=$6 max=$7
  sed -E 's/\bG80\b|\bG64\b|\bG94\b//g; s/T([0-9]+) ?M0?6/M06 T\1/; s/S[0-9.]+//g' "$corpus/$name/$name.nc" > "$out/$name.ngc"
  python3 - "$out/$name.toml" "$kind" "$diameter" "$min" "$max" <<'PY'
import sys
path, kind, diameter, lo, hi = sys.argv[1:]
lo = [float(v) for v in lo.split(",")]
hi = [float(v) for v in hi.split(",")]
size = ", ".join(f"{h - l:g}" for l, h in zip(lo, hi))
origin = ", ".join(f"{-l:g}" for l in lo)
open(path, "w").write(f'units = "mm"\n[[tools]]\nnumber = 1\nkind = "{kind}"\ndiameter = {diameter}\n'
                      f"[stock]\nsize = [{size}]\norigin = [{origin}]\n")
PY
}
