#!/usr/bin/env python3
"""The accuracy benchmark: every output of the default method against the path tracer, on real scenes.

For each scene of ACCURACY_SCENES (three Blender-style exports written by
bench/accuracy/blender_scenes.py, RenderPark's classroom, office2 and hospital, McGuire's Cornell box,
RenderPark's cube seen from behind its one-sided walls, Blender's own export of shared/samples), it
runs what a user runs and compares, at the same points:

  vertices   `lambert solve --export-vertices` (the values the glb's COLOR_0 and the viewer show):
             outgoing radiance L at up to --points points of the solution's own vertices, picked
             evenly through the file;
  lux        `lambert solve --points … --export-points` at the same points: the meter's E in lux;
  lightmap   texels of the lightmaps `lambert solve --lightmaps` bakes (bench/lightmap_texels: the
             same bake at a 256-texel atlas), up to --points of them, at the points they were baked
             at: E in lux;

against bench/vertex_reference (the project's path tracer, reference/reference.h) at those very
points, traced twice with independent seeds. The reference is the mean of the two; its noise is
half the RMS of their difference over the mean reference (the standard error of the mean), and the
samples per point are quadrupled until it is at most 1% or --max-samples (it is reported per scene).

Points are reported in three groups, none dropped (classify()): `open` (the main figures),
`discontinuity` (the meter's reading changes by more than a third within 0.5% of the scene's diagonal
along the surface: a shadow or sun edge, an emitter's rim, an edge shared with another surface, where
an interpolated vertex value cannot equal a point value) and `enclosed` (the path tracer finds no light
at all: inside a closed object, under a block). A vertex whose albedo is not one value (on a
textured face, whose texture the tracer averages over the face and a solution over each element;
on faces of different albedo at once, a board drawn in its wall's plane: vertex_reference --mixed)
is held apart from the vertex figures as `mixed`: its outgoing radiance is a blend; its lux, which
the albedo does not enter, is compared as usual. Figures per group: relative RMSE (RMSE over the mean
reference, as `lambert compare` reports it), bias (mean over mean reference − 1), and the RMS of
per-point relative errors over points whose reference is at least 10% of the mean. In the enclosed
group, where the reference is zero, the figure is the leak: lambert's mean value there over the open
points' mean reference.

Prints one JSON document; --markdown FILE also writes the table docs/accuracy.md holds.

    bench/accuracy_bench.py --lambert build/bin/lambert --vertex-reference build/bin/vertex_reference \
        --lightmap-texels build/bin/lightmap_texels [--corpus real-scenes] [--scenes blender-room,rpk-office2] [--points 300]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LUMENS_PER_WATT = 683.0

# id, where the file is ("generated": bench/accuracy/blender_scenes.py; "corpus": under --corpus;
# "repo": in this repository or beside it), its path, lambert options (RenderPark's scripts keep its
# default of forcing every face one-sided: --sides one).
ACCURACY_SCENES = [
    {"id": "blender-room", "from": "generated", "file": "blender-room.gltf", "options": []},
    {"id": "blender-panel", "from": "generated", "file": "blender-panel.gltf", "options": []},
    {"id": "blender-window", "from": "generated", "file": "blender-window.gltf", "options": []},
    {"id": "rpk-classroom", "from": "corpus", "file": "renderpark/etc/salon/classroom.mgf", "options": ["--sides", "one"]},
    {"id": "rpk-office2", "from": "corpus", "file": "renderpark/etc/office2/office2.mgf", "options": ["--sides", "one"]},
    {"id": "rpk-hospital", "from": "corpus", "file": "renderpark/etc/hospital/hosp.mgf", "options": ["--sides", "one"]},
    {"id": "mcguire-cornell", "from": "corpus", "file": "mcguire-cornell/scenes/CornellBox-Original.obj", "options": []},
    {"id": "rpk-cube-one-sided", "from": "corpus", "file": "renderpark/etc/cube.mgf", "options": ["--sides", "one"]},
    {"id": "blender-sample", "from": "repo", "file": "tests/data/blender_room.glb", "options": []},
]


def log(message):
    print(f"accuracy_bench: {message}", file=sys.stderr, flush=True)


def read_vertex_file(path):
    """lambert's vertex CSV: x,y,z,nx,ny,nz,r,g,b (header first)."""
    rows = []
    with open(path) as f:
        reader = csv.reader(f)
        header = next(reader)
        for row in reader:
            if row:
                rows.append([float(v) for v in row[:9]])
    return header, rows


def write_vertex_file(path, header, rows):
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        for row in rows:
            writer.writerow([repr(v) for v in row])


def luminance(r, g, b):
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def file_point(extension, p):
    """A scene point in the file's own frame (--points takes file coordinates): MGF is z-up, turned
    to lambert's y-up as (x, z, −y)."""
    if extension == ".mgf":
        return (p[0], -p[2], p[1])
    return tuple(p)


def errors(values, references):
    """Relative RMSE, bias and per-point relative RMS of paired scalar lists."""
    n = len(values)
    if n == 0:
        return {"points": 0}
    mean_ref = sum(references) / n
    mean_val = sum(values) / n
    rmse = math.sqrt(sum((v - r) ** 2 for v, r in zip(values, references)) / n)
    floor = 0.1 * mean_ref
    relative = [(v - r) / r for v, r in zip(values, references) if r > floor and r > 0]
    return {"points": n, "mean_reference": mean_ref,
            "relative_rmse": rmse / mean_ref if mean_ref > 0 else None,
            "bias": mean_val / mean_ref - 1 if mean_ref > 0 else None,
            "pointwise_relative_rms": math.sqrt(sum(e * e for e in relative) / len(relative)) if relative else None}


def run(command, **kwargs):
    started = time.monotonic()
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} exited {result.returncode}: {result.stderr.strip()[-2000:]}")
    return result, time.monotonic() - started


def sides_of(entry):
    """lambert's --sides value among the entry's options ("file" where it gives none)."""
    options = entry["options"]
    return options[options.index("--sides") + 1] if "--sides" in options else "file"


def trace(args, scene, entry, points_file, work, irradiance, mixed=None):
    """The reference at the points, seeds 1 and 2, samples quadrupled until its noise is ≤ 1%.
    Returns (per-point luminance of the mean of both, noise, samples). mixed, a list, receives the
    indices of the points that lie on faces of different albedo at once (vertex_reference --mixed)."""
    samples = args.samples
    while True:
        halves = []
        for seed in (1, 2):
            out = os.path.join(work, f"ref-{os.path.basename(points_file)}-{'E' if irradiance else 'L'}-{seed}.csv")
            command = [args.vertex_reference, "--scene", scene, "--sides", sides_of(entry), "--vertices", points_file,
                       "--samples", str(samples), "--seed", str(seed), "-o", out] + (["--irradiance"] if irradiance else [])
            if mixed is not None and seed == 1:
                command += ["--mixed", out + ".mixed"]
            run(command)
            if mixed is not None and seed == 1:
                with open(out + ".mixed") as f:
                    mixed[:] = [int(line) for line in f if line.strip()]
            halves.append([luminance(*row[6:9]) for row in read_vertex_file(out)[1]])
        a, b = halves
        mean = [(x + y) / 2 for x, y in zip(a, b)]
        mean_ref = sum(mean) / len(mean) if mean else 0
        noise = math.sqrt(sum(((x - y) / 2) ** 2 for x, y in zip(a, b)) / len(a)) / mean_ref if mean_ref > 0 else 0
        if noise <= 0.01 or samples >= args.max_samples:
            return mean, noise, samples
        samples *= 4


def meter(args, path, entry, extension, points, work, name):
    """lambert's meter (`solve --points`) in lux at scene points (position, normal)."""
    meter_in, meter_out = os.path.join(work, name + ".csv"), os.path.join(work, name + "-lux.csv")
    with open(meter_in, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["x", "y", "z", "nx", "ny", "nz"])
        for p in points:
            writer.writerow([repr(v) for v in file_point(extension, p[0:3]) + file_point(extension, p[3:6])])
    run([args.lambert, "solve", "--scene", path, *entry["options"], "--points", meter_in, "--export-points", meter_out])
    with open(meter_out) as f:
        return [float(row["E"]) for row in csv.DictReader(f)]


def classify(args, path, entry, extension, points, reference_e, work):
    """Per point: 'enclosed' where the path tracer finds no light at all (inside a closed object,
    under a block: black by construction), 'discontinuity' where the meter's reading changes by more
    than a third within --discontinuity-radius (a fraction of the scene's diagonal) along the surface
    (a shadow or sun edge, the rim of an emitter, an edge shared with another surface: where a vertex
    value, interpolated, cannot equal a point value), 'open' elsewhere."""
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    radius = args.discontinuity_radius * math.sqrt(sum((h - l) ** 2 for h, l in zip(hi, lo)))
    probes = []
    for p in points:
        n = normalised_vector(p[3:6])
        helper = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
        u = normalised_vector(cross_vector(n, helper))
        w = cross_vector(n, u)
        for a, b in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            probes.append(tuple(p[k] + radius * (a * u[k] + b * w[k]) for k in range(3)) + tuple(n))
    around = meter(args, path, entry, extension, probes, work, "around")
    groups = []
    for i, e in enumerate(reference_e):
        readings = around[4 * i: 4 * i + 4]
        if e == 0:
            groups.append("enclosed")
        elif max(readings) - min(readings) > max(readings) / 3:
            groups.append("discontinuity")
        else:
            groups.append("open")
    return groups


def normalised_vector(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v) if n > 0 else (0.0, 1.0, 0.0)


def cross_vector(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def measure_scene(args, entry, path):
    extension = os.path.splitext(path)[1].lower()
    with tempfile.TemporaryDirectory(prefix=f"accuracy-{entry['id']}-") as work:
        vertices_file = os.path.join(work, "vertices.csv")
        solve = [args.lambert, "solve", "--scene", path, *entry["options"], "--export-vertices", vertices_file, "--json"]
        result, solve_seconds = run(solve)
        stats = json.loads(result.stdout)
        header, rows = read_vertex_file(vertices_file)
        # Points evenly through the file (its vertices run surface by surface, so every surface gets its share).
        step = max(1, len(rows) // args.points)
        picked = rows[::step][: args.points]
        points_file = os.path.join(work, "points.csv")
        write_vertex_file(points_file, header, picked)
        lux = meter(args, path, entry, extension, picked, work, "meter")
        mixed = []
        reference_l, noise_l, samples_l = trace(args, path, entry, points_file, work, irradiance=False, mixed=mixed)
        reference_e, noise_e, samples_e = trace(args, path, entry, points_file, work, irradiance=True)
        # The lightmap: texels of the default method's bake, with their points, against the tracer there.
        texels_file = os.path.join(work, "texels.csv")
        quality = ["--link-error", repr(args.link_error)] if args.link_error is not None else []
        run([args.lightmap_texels, "--scene", path, "--sides", sides_of(entry), "--texels", str(args.points), *quality, "-o", texels_file])
        texel_rows = read_vertex_file(texels_file)[1]
        texel_lux = [LUMENS_PER_WATT * luminance(*row[6:9]) for row in texel_rows]
        texel_reference_e, noise_t, samples_t = trace(args, path, entry, texels_file, work, irradiance=True)
        texel_reference_lux = [LUMENS_PER_WATT * e for e in texel_reference_e]
        texel_groups = classify(args, path, entry, extension, texel_rows, texel_reference_e, work)
        reference_lux = [LUMENS_PER_WATT * e for e in reference_e]
        vertex_l = [luminance(*row[6:9]) for row in picked]
        groups = classify(args, path, entry, extension, picked, reference_e, work)
        # A vertex whose albedo is not one value (a textured face, a board drawn in its wall's plane)
        # shows a blend: its outgoing radiance is held apart, its irradiance is not.
        vertex_groups = ["mixed" if i in set(mixed) else g for i, g in enumerate(groups)]
        if args.keep:
            os.makedirs(args.keep, exist_ok=True)
            with open(os.path.join(args.keep, entry["id"] + "-points.csv"), "w", newline="") as f:
                writer = csv.writer(f)
                writer.writerow(["x", "y", "z", "nx", "ny", "nz", "L_vertex", "L_reference", "lux_meter", "lux_reference", "group"])
                for row, v, r, m, e, g in zip(picked, vertex_l, reference_l, lux, reference_lux, vertex_groups):
                    writer.writerow([f"{c:.6g}" for c in row[:6]] + [f"{v:.6g}", f"{r:.6g}", f"{m:.6g}", f"{e:.6g}", g])
            with open(os.path.join(args.keep, entry["id"] + "-texels.csv"), "w", newline="") as f:
                writer = csv.writer(f)
                writer.writerow(["x", "y", "z", "nx", "ny", "nz", "lux_texel", "lux_reference", "group"])
                for row, v, r, g in zip(texel_rows, texel_lux, texel_reference_lux, texel_groups):
                    writer.writerow([f"{c:.6g}" for c in row[:6]] + [f"{v:.6g}", f"{r:.6g}", g])
        report = {"id": entry["id"], "file": os.path.relpath(path, ROOT) if path.startswith(ROOT) else os.path.basename(path),
                  "options": entry["options"], "vertices": len(rows), "points": len(picked),
                  "solve_seconds": solve_seconds, "leaves": stats.get("patches"),
                  "reference": {"radiance_noise": noise_l, "radiance_samples": samples_l,
                                "irradiance_noise": noise_e, "irradiance_samples": samples_e,
                                "texel_noise": noise_t, "texel_samples": samples_t},
                  "texels": len(texel_rows), "texel_groups": {g: texel_groups.count(g) for g in sorted(set(texel_groups))},
                  "groups": {g: groups.count(g) for g in sorted(set(groups))}, "mixed_vertices": len(mixed)}
        report["leak"] = {}
        for name, values, references, point_groups in (("vertices", vertex_l, reference_l, vertex_groups), ("lux", lux, reference_lux, groups),
                                                       ("lightmap", texel_lux, texel_reference_lux, texel_groups)):
            open_refs = [r for r, g in zip(references, point_groups) if g == "open"]
            enclosed = [v for v, g in zip(values, point_groups) if g == "enclosed"]
            open_mean = sum(open_refs) / len(open_refs) if open_refs else 0
            report["leak"][name] = sum(enclosed) / len(enclosed) / open_mean if enclosed and open_mean > 0 else None
            report[name] = {}
            for group in sorted(set(point_groups)):
                pairs = [(v, r) for v, r, g in zip(values, references, point_groups) if g == group]
                report[name][group] = errors([p[0] for p in pairs], [p[1] for p in pairs])
        return report


def markdown(reports):
    """The table of docs/accuracy.md: per scene, the open points' relative RMSE and bias of each output."""
    lines = ["| scene | points: open / discontinuity / enclosed (mixed albedo) | tracer noise | vertices: RMSE, bias | lux: RMSE, bias | "
             "lightmap texels: RMSE, bias | at discontinuities: vertices, lux, texels | enclosed leak: vertices, lux, texels | solve |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    pct = lambda x: "—" if x is None else f"{100 * x:+.1f}%"
    mag = lambda x: "—" if x is None else f"{100 * x:.1f}%"
    for r in reports:
        if "error" in r:
            lines.append(f"| {r['id']} | {r['error']} | | | | | | | |")
            continue
        g = r["groups"]
        noise = max(r["reference"][k] for k in ("radiance_noise", "irradiance_noise", "texel_noise"))
        cells = []
        for output in ("vertices", "lux", "lightmap"):
            o = r[output].get("open", {})
            cells.append(f"{mag(o.get('relative_rmse'))}, {pct(o.get('bias'))}")
        at = ", ".join(mag(r[o].get("discontinuity", {}).get("relative_rmse")) for o in ("vertices", "lux", "lightmap"))
        leak = ", ".join(mag(r["leak"][o]) for o in ("vertices", "lux", "lightmap"))
        lines.append(f"| {r['id']} | {g.get('open', 0)} / {g.get('discontinuity', 0)} / {g.get('enclosed', 0)} ({r['mixed_vertices']}) | {mag(noise)} | "
                     f"{' | '.join(cells)} | {at} | {leak} | {r['solve_seconds']:.2f} s |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lambert", default=os.path.join(ROOT, "build/bin/lambert"))
    parser.add_argument("--vertex-reference", default=os.path.join(ROOT, "build/bin/vertex_reference"))
    parser.add_argument("--lightmap-texels", default=os.path.join(ROOT, "build/bin/lightmap_texels"))
    parser.add_argument("--corpus", default=os.path.join(ROOT, "real-scenes"))
    parser.add_argument("--scenes", default="", help="comma-separated ids (default: all)")
    parser.add_argument("--points", type=int, default=300, help="points per scene (from the solution's vertices), and as many texels")
    parser.add_argument("--samples", type=int, default=4096, help="first reference samples per point and seed")
    parser.add_argument("--max-samples", type=int, default=16384, help="the most reference samples per point and seed")
    parser.add_argument("--link-error", type=float, default=None,
                        help="lambert's --link-error for every run of the default method (the quality setting: 2e-5)")
    parser.add_argument("--discontinuity-radius", type=float, default=0.005,
                        help="how far round a point the meter looks for a discontinuity, a fraction of the scene's diagonal")
    parser.add_argument("--markdown", help="also write the table here")
    parser.add_argument("--keep", help="write each scene's points (value and reference, per output) as ID-points.csv here")
    args = parser.parse_args()

    wanted = set(filter(None, args.scenes.split(",")))
    with tempfile.TemporaryDirectory(prefix="accuracy-scenes-") as generated:
        reports = measure_all(args, wanted, generated)
    if args.markdown:
        with open(args.markdown + ".tmp", "w") as f:
            f.write(markdown(reports))
        os.replace(args.markdown + ".tmp", args.markdown)
    json.dump({"scenes": reports}, sys.stdout, indent=1)
    print()
    return 0


def measure_all(args, wanted, generated):
    """Every wanted scene's report (or why it was skipped), the Blender-style ones written to `generated`."""
    subprocess.run([sys.executable, os.path.join(ROOT, "bench/accuracy/blender_scenes.py"), "--out", generated],
                   check=True, capture_output=True)
    reports = []
    for entry in ACCURACY_SCENES:
        if wanted and entry["id"] not in wanted:
            continue
        base = {"generated": generated, "corpus": args.corpus, "repo": ROOT}[entry["from"]]
        path = os.path.join(base, entry["file"])
        if not os.path.exists(path):
            reports.append({"id": entry["id"], "error": f"skipped: {entry['file']} is not in {base} (scripts/fetch-corpus.py brings it)"})
            log(reports[-1]["error"])
            continue
        log(f"{entry['id']}: {path}")
        if args.link_error is not None:
            entry = dict(entry, options=entry["options"] + ["--link-error", repr(args.link_error)])
        try:
            reports.append(measure_scene(args, entry, path))
        except RuntimeError as e:
            reports.append({"id": entry["id"], "error": str(e)})
            log(str(e))
    return reports


if __name__ == "__main__":
    sys.exit(main())
