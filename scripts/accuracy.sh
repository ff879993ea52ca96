#!/usr/bin/env bash
# The accuracy table: every form-factor method × patch count × sample setting on the Cornell box,
# measured against the path-traced reference at the same vertices, with its time. Writes
# docs/accuracy.md (the table, for README) and docs/images/accuracy.png (error against time, one
# line per method at its default setting). Slow: the 10,000-patch rows take minutes each.
#   scripts/accuracy.sh                 # the full table
#   PATCHES="192 784" scripts/accuracy.sh   # a quick one
set -euo pipefail
cd "$(dirname "$0")/.."

# gnuplot draws the plot, python3 reads the JSON; both from Debian, only if missing.
need=()
command -v gnuplot > /dev/null || need+=(gnuplot-nox)
command -v python3 > /dev/null || need+=(python3)
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then as_root=(); else as_root=(sudo); fi
  "${as_root[@]}" apt-get update -qq && DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get install -y -qq "${need[@]}"
fi
make -s build > /dev/null
lambert=build/bin/lambert

PATCHES=${PATCHES:-"192 304 464 784 3000 10000"}
REFERENCE_SAMPLES=${REFERENCE_SAMPLES:-4096}
work=${WORK:-/tmp/lambert-accuracy}
mkdir -p "$work" docs/images
results="$work/results.jsonl"
: > "$results"

# method, its option, and the settings to try (the default one first); the point-to-point method has
# no setting (one kernel and one ray per pair).
settings=(
  "point||-"
  "mc|--samples|16 4 64"
  "hemicube|--hemicube-resolution|256 64"
  "hemisphere|--hemisphere-rays|1024 256 4096"
)

for patches in $PATCHES; do
  reference="$work/reference-$patches.csv"
  if [ ! -f "$reference" ]; then
    echo "reference at $patches patches ($REFERENCE_SAMPLES samples a vertex)" >&2
    $lambert reference --patches "$patches" --vertex-samples "$REFERENCE_SAMPLES" --export-vertices "$reference" -q
  fi
  for entry in "${settings[@]}"; do
    IFS='|' read -r method option values <<< "$entry"
    first=1
    [ -z "$option" ] && values="-"
    for value in $values; do
      setting=()
      [ -n "$option" ] && setting=("$option" "$value")
      echo "  $method $option $value at $patches patches" >&2
      vertices="$work/$method-$value-$patches.csv"
      # No cache: the table times the computation.
      solve=$($lambert solve --patches "$patches" --formfactor "$method" "${setting[@]}" --no-cache \
                --export-vertices "$vertices" --json)
      compare=$($lambert compare --radiosity-vertices "$vertices" --reference-vertices "$reference" --json)
      python3 - "$method" "$option" "$value" "$first" <<PY >> "$results"
import json, sys
solve = json.loads('''$solve''')
compare = json.loads('''$compare''')
method, option, value, first = sys.argv[1:]
print(json.dumps({"method": method, "setting": f"{option.lstrip('-')} {value}" if option else "one ray", "default": first == "1",
                  "patches": solve["patches"], "formfactor_seconds": solve["formfactor_seconds"],
                  "solve_seconds": solve["solve_seconds"], "relative_rmse": compare["vertex_relative_rmse"],
                  "max_relative": compare["vertex_max_rel"], "bias": compare["vertex_bias"]}))
PY
      first=0
    done
  done
done

python3 - "$results" "$work" <<'PY'
import json, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
work = sys.argv[2]
# What follows the marker (the hierarchical method's figures) is kept.
marker = "<!-- The table above is written by scripts/accuracy.sh; what follows is kept. -->"
try:
    kept = open("docs/accuracy.md").read().split(marker, 1)
    kept = marker + kept[1] if len(kept) == 2 else ""
except FileNotFoundError:
    kept = ""
with open("docs/accuracy.md", "w") as out:
    out.write("| method | setting | patches | form factors | solve | vertex relative RMSE | bias | max relative |\n")
    out.write("|---|---|---:|---:|---:|---:|---:|---:|\n")
    for r in rows:
        out.write(f"| {r['method']} | {r['setting']} | {r['patches']:,} | {r['formfactor_seconds']:.3g} s | "
                  f"{r['solve_seconds']:.2g} s | {100 * r['relative_rmse']:.1f}% | {100 * r['bias']:+.1f}% | "
                  f"{100 * r['max_relative']:.0f}% |\n")
    if kept:
        out.write("\n" + kept)
for method in sorted({r["method"] for r in rows}):
    with open(f"{work}/plot-{method}.dat", "w") as data:
        for r in rows:
            if r["method"] == method and r["default"]:
                data.write(f"{r['formfactor_seconds'] + r['solve_seconds']:.6g} {100 * r['relative_rmse']:.6g} {r['patches']}\n")
PY

gnuplot <<GP
set terminal pngcairo size 900,600 font ",11"
set output "docs/images/accuracy.png"
set title "Cornell box: per-vertex error against the path-traced reference"
set xlabel "form factors + solve (s, 2-core machine)"
set ylabel "vertex relative RMSE (%)"
set logscale xy
set grid
set key top right
plot for [m in "point mc hemicube hemisphere"] "$work/plot-".m.".dat" using 1:2 with linespoints lw 2 pt 7 title m, \
     for [m in "mc"] "$work/plot-".m.".dat" using 1:2:3 with labels offset 0,1 notitle
GP
echo "wrote docs/accuracy.md and docs/images/accuracy.png" >&2
