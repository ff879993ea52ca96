#!/usr/bin/env bash
# bench/accuracy_bench.py on its first Blender-style scene, with few points and samples, so that
# `make bench`'s accuracy part cannot rot, and so that the two mechanisms it found stay fixed: a
# curved surface's vertices evaluated inside it (the room's sphere at 16% vertex RMSE) and light
# handed to the inside of closed two-sided objects (22% of the room's mean there).
#   tests/accuracy_bench_test.sh LAMBERT VERTEX_REFERENCE LIGHTMAP_TEXELS SOURCE_DIR SCRATCH_DIR
set -euo pipefail
lambert="$1"; reference="$2"; texels="$3"; source_dir="$4"; scratch="$5"
mkdir -p "$scratch"
python3 "$source_dir/bench/accuracy_bench.py" --lambert "$lambert" --vertex-reference "$reference" --lightmap-texels "$texels" \
  --scenes blender-room --points 60 --samples 1024 --max-samples 1024 --markdown "$scratch/accuracy.md" > "$scratch/accuracy.json"
exec python3 - "$scratch/accuracy.json" "$scratch/accuracy.md" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))["scenes"]
def check(condition, what):
    if not condition:
        sys.exit(f"accuracy_bench_test: FAILED: {what}")
check(len(report) == 1 and report[0]["id"] == "blender-room" and "error" not in report[0], f"one scene measured: {report}")
room = report[0]
noise = max(room["reference"][k] for k in ("radiance_noise", "irradiance_noise", "texel_noise"))
check(0 < noise < 0.03, f"the tracer's own noise at 1024 samples: {noise}")
check(room["groups"].get("open", 0) >= 20, f"open points: {room['groups']}")
# Each output within 5% of the tracer on the open points, beyond the tracer's own noise.
for output in ("vertices", "lux", "lightmap"):
    rmse = room[output]["open"]["relative_rmse"]
    check(rmse < 0.05 + noise, f"{output}: {rmse:.3f} relative RMSE on the open points")
    bias = room[output]["open"]["bias"]
    check(abs(bias) < 0.03, f"{output}: bias {bias:+.3f}")
# The inside of the sphere, the table top and the legs: dark, as the tracer finds it.
check(room["groups"].get("enclosed", 0) > 0, "no enclosed point")
for output in ("vertices", "lux", "lightmap"):
    leak = room["leak"][output]
    check(leak is None or leak < 0.05, f"{output}: enclosed points show {leak:.3f} of the open mean")
check(open(sys.argv[2]).read().count("| blender-room |") == 1, "the markdown table")
print("accuracy_bench_test: ok")
PY
