#!/usr/bin/env bash
# bench/default_method_bench.py in its --quick mode, so that `make bench`'s default-method part
# cannot rot: whole-process timings with a spread, the Cornell box against a path-traced
# reference traced at the solve's own vertices (bench/vertex_reference), that reference's noise,
# its cache, the buildings and the link-cache case; RenderPark is run where it is built beside
# the project and skipped with a reason otherwise.
#   tests/default_method_bench_test.sh LAMBERT_BINARY VERTEX_REFERENCE_BINARY SOURCE_DIR SCRATCH_DIR
set -euo pipefail
lambert="$1"; vertex_reference="$2"; source_dir="$3"; scratch="$4"
fail() { echo "default_method_bench_test: FAILED: $*" >&2; exit 1; }
rm -rf "$scratch"; mkdir -p "$scratch"
bench() { python3 "$source_dir/bench/default_method_bench.py" --quick --lambert "$lambert" --vertex-reference "$vertex_reference" \
            --out "$scratch/out" "$@"; }

bench > "$scratch/first.json" 2> "$scratch/first.log" || { cat "$scratch/first.log" >&2; fail "the quick run failed"; }
# A second run finds every reference in the cache and, the solves being deterministic, gives the same errors.
bench > "$scratch/second.json" 2> "$scratch/second.log" || { cat "$scratch/second.log" >&2; fail "the second quick run failed"; }
grep -q "reference: " "$scratch/second.log" && fail "the second run traced a reference again instead of reading the cache"

# vertex_reference refuses a vertex that lies on no surface of the scene (its albedo would be a guess),
# naming the file, the vertex and its line, and writes nothing.
printf 'x,y,z,nx,ny,nz,r,g,b\n278,0,280,0,1,0,0,0,0\n278,-50,280,0,1,0,0,0,0\n' > "$scratch/off.csv"
status=0; "$vertex_reference" --scene cornell --vertices "$scratch/off.csv" --samples 4 -o "$scratch/off-reference.csv" \
  2> "$scratch/off.log" || status=$?
[ "$status" = 2 ] || fail "vertex_reference exited $status on a vertex off every surface (expected 2)"
grep -q "off.csv: vertex 1 (data line 2) at (278, -50, 280) lies on no face" "$scratch/off.log" || { cat "$scratch/off.log" >&2; fail "the refusal's message"; }
[ ! -e "$scratch/off-reference.csv" ] || fail "vertex_reference wrote a file for a refused input"

# The Cornell box's error measured by the CLI's own compare (its tracer at the same solve's vertices, in process).
"$lambert" compare --scene cornell --no-image --vertex-samples 256 --json > "$scratch/compare.json" || fail "lambert compare failed"

python3 - "$scratch" <<'PY'
import json, math, sys
scratch = sys.argv[1]
first, second = (json.load(open(f"{scratch}/{n}.json")) for n in ("first", "second"))
cli = json.load(open(f"{scratch}/compare.json"))
def check(condition, what):
    if not condition:
        sys.exit(f"default_method_bench_test: FAILED: {what}")
for name in ("default", "quality"):
    row = first["cornell"][name]
    w = row["wall_seconds"]
    check(0 < w["min"] <= w["median"] <= w["max"], f"{name}: wall seconds {w}")
    check(row["peak_rss_mib"] > 1, f"{name}: peak RSS {row['peak_rss_mib']}")
    check(0 < row["vertex_relative_rmse"] < 0.5, f"{name}: error {row['vertex_relative_rmse']}")
    check(0 < row["reference_noise"] < row["vertex_relative_rmse"], f"{name}: reference noise {row['reference_noise']}")
    check(row["vertices_compared"] > 1000, f"{name}: {row['vertices_compared']} vertices compared")
    check(not row["reference_from_cache"] and second["cornell"][name]["reference_from_cache"], f"{name}: the reference cache")
    check(second["cornell"][name]["vertex_relative_rmse"] == row["vertex_relative_rmse"], f"{name}: the error changed between runs")
# The finer link error refines further.
check(first["cornell"]["quality"]["leaves"] > first["cornell"]["default"]["leaves"], "link error 1e-4 made no more leaves than 2e-4")
# Two estimators of the same error at 256 samples: this bench's (vertex_reference, the vertices out of
# the exported file) and compare's (its own tracer at the solution's vertex mesh), each with ~4% noise.
mine, theirs = first["cornell"]["default"]["vertex_relative_rmse"], cli["vertex_relative_rmse"]
check(abs(mine - theirs) < 0.1 * theirs, f"the bench's error {mine} and lambert compare's {theirs} disagree")
building = first["building"]["rows"][0]
check(building["faces"] > 1000 and building["converged"] == "yes", f"building: {building}")
cache = first["link_cache"]
check(cache["available"] is True and cache["speedup"] > 0 or cache["why"].startswith("not available"), f"link cache: {cache}")
rpk = first["renderpark"]
check("skipped" in rpk or all(0 < r["vertex_relative_rmse"] < 0.5 for r in rpk["runs"]), f"RenderPark: {rpk}")
check(first["bench_seconds"] > 0, "bench_seconds")
PY
echo "default_method_bench_test: passed"
