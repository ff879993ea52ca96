#!/usr/bin/env python3
"""The default method (hierarchical radiosity) timed as a user waits for it, beside RenderPark.

Every time is the whole process's wall time of the `lambert` CLI, from process start to its
written output file (`lambert solve ... --export-vertices FILE`: loading, hierarchy, BVH, link
refinement, solve and the final gather that gives the vertex values), the median of --runs runs
with their min and max, and the child's peak resident memory (wait4's ru_maxrss). Each cold run
gets an empty cache directory of its own (XDG_CACHE_HOME), so no run reads what another wrote.

  cornell      the built-in Cornell box at the default settings and at --quality-link-error, each
               with its per-vertex relative RMSE (`lambert compare`'s metric: vertices by the
               light's rim and inside geometry left out) against a path-traced reference at the
               solve's own exported vertices, and that reference's own noise beside it.
  renderpark   RenderPark's Galerkin hierarchical radiosity with clustering (its defaults) on the
               same box, written as MGF in RenderPark's colour model, at several ε, its error
               against the same kind of reference at its own element corners (and with the corners
               elements share averaged, as its Gouraud display shows them: the error the ratio is
               taken at), and lambert's speed ratio at RenderPark's best error (lambert's time
               interpolated, log-log, along its curve of time against error over
               --curve-link-errors). Skipped, with the reason,
               where RenderPark is not built beside the project.
  building     generated buildings (`lambert generate building --rooms N --face-size 0.25`),
               whole-process `lambert solve`, peak memory, and the growth exponent of time in
               faces with its uncertainty from the runs' spread.
  link_cache   the 10^5-face building solved twice with one fresh --cache-dir: first against
               second run ("not available", with the reason, where the CLI caches no links).

References. `vertex_reference` (bench/vertex_reference.cpp) path-traces the outgoing radiance at
a vertex file's own points. Each reference is two independent halves (seeds 1 and 2, half the
samples each), averaged; the relative RMSE of their difference (the compare metric) is √2 times
one half's noise and twice the average's, so `reference_noise` is that RMSE / 2. References are
cached in OUT/references/, keyed by the scene, the samples and the vertex positions and normals,
and written atomically, so repeated runs trace only vertices they have not seen.

Prints one JSON document on stdout; progress on stderr.

    bench/default_method_bench.py [--quick] [--runs 3] [--no-million] [--out out/bench/default_method]
                                  [--quality-link-error 1e-5] [--reference-samples 32768]
                                  [--renderpark PATH] [--rooms 1,8,64,640]
"""
import argparse
import hashlib
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from corpus_bench import machine  # the same machine record in both benchmarks' JSON

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_LINK_ERROR = 2e-4  # lambert's --link-error default (its --help), for the curve's first point

# The default method's targets (2-core machine).
TARGETS = {
    "cornell_default": {"vertex_relative_rmse_max": 0.03, "wall_seconds_max": 0.5},
    "cornell_quality": {"vertex_relative_rmse_max": 0.015, "wall_seconds_max": 2.0},
    "reference_noise_max": 0.005,
    "renderpark_speed_ratio_min": 3.0,
    "building_1e6": {"wall_seconds_max": 30.0, "peak_rss_mib_max": 2048.0},
    "link_cache_speedup_min": 5.0,
}


def log(message):
    print(f"default_method_bench: {message}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# Running a process as a user does.

def run_once(command, timeout, env_extra=None, cwd=None):
    """Runs command to completion: wall seconds from start to exit, the child's own peak RSS
    (wait4), exit status, stdout and stderr (through files, so a chatty child never blocks)."""
    env = dict(os.environ)
    env.update(env_extra or {})
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.monotonic()
        child = subprocess.Popen(command, stdout=out, stderr=err, env=env, cwd=cwd)
        deadline = start + timeout
        status, usage = None, None
        while True:
            pid, status, usage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() > deadline:
                child.kill()
                _, status, usage = os.wait4(child.pid, 0)
                break
            time.sleep(0.002)
        wall = time.monotonic() - start
        child.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        timed_out = wall > timeout
        return {"rc": None if timed_out else child.returncode, "wall": wall, "rss_mib": usage.ru_maxrss / 1024,
                "out": out.read().decode(errors="replace"), "err": err.read().decode(errors="replace"),
                "timed_out": timed_out}


def first_error(run):
    if run.get("timed_out"):
        return "timed out"
    lines = run["err"].strip().splitlines()
    return next((line for line in lines if "error" in line.lower() or ": " in line), lines[-1] if lines else f"exit {run['rc']}")


def spread(values):
    return {"median": round(statistics.median(values), 4), "min": round(min(values), 4), "max": round(max(values), 4),
            "runs": [round(v, 4) for v in values]}


def timed_runs(command, runs, timeout, scratch, label):
    """`runs` cold runs of command, each with an empty cache directory: the wall-time spread, the
    largest peak RSS, and the last run's JSON stats (the command prints --json). None and the
    reason when a run fails."""
    walls, rss, stats = [], [], {}
    for k in range(runs):
        cache = tempfile.mkdtemp(prefix="cache-", dir=scratch)
        log(f"{label}: run {k + 1} of {runs}")
        r = run_once(command, timeout, {"XDG_CACHE_HOME": cache})
        shutil.rmtree(cache, ignore_errors=True)
        if r["rc"] != 0:
            return None, f"{' '.join(command)}: {first_error(r)}"
        walls.append(r["wall"])
        rss.append(r["rss_mib"])
        try:
            stats = json.loads(r["out"])
        except ValueError:
            stats = {}
    return {"wall_seconds": spread(walls), "peak_rss_mib": round(max(rss), 1), "stats": stats}, None


# ---------------------------------------------------------------------------------------------
# Vertex files and references.

def read_vertices(path):
    """lambert's vertex CSV (x,y,z,nx,ny,nz,r,g,b): the header and the rows as lists of floats."""
    with open(path) as f:
        header = f.readline().strip()
        return header, [[float(v) for v in line.split(",")] for line in f if line.strip()]


def write_vertices_atomically(path, header, rows):
    folder = os.path.dirname(path) or "."
    fd, temporary = tempfile.mkstemp(prefix=".tmp-", suffix=".csv", dir=folder)
    with os.fdopen(fd, "w") as f:
        f.write(header + "\n")
        for row in rows:
            f.write(",".join(f"{v:.9g}" for v in row) + "\n")
    os.replace(temporary, path)


def vertices_key(scene, samples, path):
    """What a reference depends on: the scene, the samples and the points with their normals."""
    digest = hashlib.sha256(f"{scene}|{samples}|".encode())
    with open(path) as f:
        f.readline()
        for line in f:
            digest.update((",".join(line.split(",")[:6]) + "\n").encode())
    return digest.hexdigest()[:24]


class References:
    def __init__(self, args, scratch):
        self.args, self.scratch = args, scratch
        self.folder = os.path.join(args.out, "references")
        os.makedirs(self.folder, exist_ok=True)

    def compare(self, scene, radiosity, reference):
        """`lambert compare` on two vertex files: its JSON stats."""
        r = run_once([self.args.lambert, "compare", "--scene", scene, "--radiosity-vertices", radiosity,
                      "--reference-vertices", reference, "--json"], self.args.timeout)
        if r["rc"] != 0:
            raise RuntimeError(f"lambert compare: {first_error(r)}")
        return json.loads(r["out"])

    def reference(self, scene, vertices, samples):
        """The reference at a vertex file's points: (path, its noise, metadata). Traced as two
        halves of different seeds, or read from the cache."""
        key = vertices_key(scene, samples, vertices)
        path = os.path.join(self.folder, key + ".csv")
        meta_path = os.path.join(self.folder, key + ".json")
        if os.path.exists(path) and os.path.exists(meta_path):
            with open(meta_path) as f:
                meta = json.load(f)
            meta["from_cache"] = True
            return path, meta
        halves, seconds = [], 0.0
        for seed in (1, 2):
            half = os.path.join(self.scratch, f"{key}-seed{seed}.csv")
            log(f"reference: {samples // 2} samples a vertex, seed {seed}, at {os.path.basename(vertices)}")
            r = run_once([self.args.vertex_reference, "--scene", scene, "--vertices", vertices, "--samples", str(samples // 2),
                          "--seed", str(seed), "-o", half], self.args.timeout * 20)
            if r["rc"] != 0:
                raise RuntimeError(f"vertex_reference: {first_error(r)}")
            seconds += r["wall"]
            halves.append(half)
        difference = self.compare(scene, halves[0], halves[1])
        header, first = read_vertices(halves[0])
        _, second = read_vertices(halves[1])
        averaged = [a[:6] + [(x + y) / 2 for x, y in zip(a[6:], b[6:])] for a, b in zip(first, second)]
        meta = {"samples": 2 * (samples // 2), "seeds": [1, 2], "vertices": len(averaged), "trace_seconds": round(seconds, 2),
                # The two halves differ by √2 × one half's noise: the average has half of that difference.
                "noise": round(difference["vertex_relative_rmse"] / 2, 5),
                "half_noise": round(difference["vertex_relative_rmse"] / math.sqrt(2), 5)}
        write_vertices_atomically(path, header, averaged)
        fd, temporary = tempfile.mkstemp(prefix=".tmp-", suffix=".json", dir=self.folder)
        with os.fdopen(fd, "w") as f:
            json.dump(meta, f)
        os.replace(temporary, meta_path)
        meta["from_cache"] = False
        return path, meta

    def error(self, scene, vertices, samples):
        """A solution's vertex file against its reference: error, bias, the reference's noise, and
        the error less that noise (in quadrature: the two are independent)."""
        reference, meta = self.reference(scene, vertices, samples)
        c = self.compare(scene, vertices, reference)
        e, n = c["vertex_relative_rmse"], meta["noise"]
        return {"vertex_relative_rmse": round(e, 5), "vertex_bias": round(c["vertex_bias"], 5),
                "vertices_compared": c["vertex_compared"] // 3, "reference_samples": meta["samples"],
                "reference_noise": n, "vertex_relative_rmse_less_noise": round(math.sqrt(max(0.0, e * e - n * n)), 5),
                "reference_from_cache": meta["from_cache"], "reference_trace_seconds": meta["trace_seconds"]}


# ---------------------------------------------------------------------------------------------
# (a) The Cornell box.

def solve_cornell(args, scratch, name, options, runs):
    """The timed runs of one setting; its error is added later (measure_error), so that every
    timing is taken before the references are traced."""
    vertices = os.path.join(args.out, f"cornell-{name}.csv")
    command = [args.lambert, "solve", "--scene", "cornell", *options, "--export-vertices", vertices, "--json"]
    measured, why = timed_runs(command, runs, args.timeout, scratch, f"cornell {name}")
    if measured is None:
        raise RuntimeError(why)
    stats = measured.pop("stats")
    return {"setting": name, "options": " ".join(options) or "(defaults)", **measured,
            "leaves": stats.get("patches"), "links": stats.get("links"), "vertices": stats.get("vertices"),
            "vertices_file": vertices}


def measure_error(references, row, samples):
    row.update(references.error("cornell", row["vertices_file"], samples))
    return row


def with_target(row, limits):
    e, t = row["vertex_relative_rmse"], row["wall_seconds"]["median"]
    row["targets"] = [{"name": "vertex_relative_rmse", "max": limits["vertex_relative_rmse_max"], "value": e,
                       "target_met": e <= limits["vertex_relative_rmse_max"]},
                      {"name": "wall_seconds_median", "max": limits["wall_seconds_max"], "value": t,
                       "target_met": t < limits["wall_seconds_max"]},
                      {"name": "reference_noise", "max": TARGETS["reference_noise_max"], "value": row["reference_noise"],
                       "target_met": row["reference_noise"] < TARGETS["reference_noise_max"]}]
    return row


# ---------------------------------------------------------------------------------------------
# (b) RenderPark on the same box.

# RenderPark reads an MGF colour (chromaticity x, y and a luminous factor Y) as RGB through the
# CIE XYZ → RGB matrix of its nominal CRT primaries with white at E (x = y = 1/3), and turns ed
# (lm/m²) into W/m² by its white efficacy, 183.07 lm/W (RenderPark's common/cie.cpp). The box is
# written so that its RGB reflectances are lambert's to 9 digits: XYZ = M · RGB, with M from those
# primaries (the standard construction: columns the primaries' XYZ scaled so RGB (1,1,1) is white).
RPK_PRIMARIES = ((0.640, 0.330), (0.290, 0.600), (0.150, 0.060))
RPK_WHITE = (1 / 3, 1 / 3)
RPK_WHITE_EFFICACY = 183.07


def solve3(a, b):
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(3):
        p = max(range(c, 3), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(3):
            if r != c:
                f = m[r][c] / m[c][c]
                m[r] = [m[r][k] - f * m[c][k] for k in range(4)]
    return [m[i][3] / m[i][i] for i in range(3)]


def rgb_to_xyz_matrix(primaries, white):
    xyz = lambda xy: [xy[0] / xy[1], 1.0, (1 - xy[0] - xy[1]) / xy[1]]
    columns = [xyz(p) for p in primaries]
    a = [[columns[j][i] for j in range(3)] for i in range(3)]
    s = solve3(a, xyz(white))
    return [[a[i][j] * s[j] for j in range(3)] for i in range(3)]


def mgf_colour(rgb):
    """(x, y, Y): the MGF chromaticity and luminous factor RenderPark reads back as rgb."""
    m = rgb_to_xyz_matrix(RPK_PRIMARIES, RPK_WHITE)
    x, y, z = (sum(m[i][j] * rgb[j] for j in range(3)) for i in range(3))
    return x / (x + y + z), y / (x + y + z), y


def write_cornell_mgf(scene_json, path):
    """The built-in box (`lambert scenes --export`) as MGF in metres (RenderPark's refinement and
    tone map depend on the scene's absolute size), one-sided, in RenderPark's colour model.
    Returns the emitters' radiance by material and the metres per scene unit."""
    with open(scene_json) as f:
        scene = json.load(f)
    metres = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254, "ft": 0.3048}[scene.get("unit", "m")]
    name = lambda s: s.replace(" ", "_")
    lines = ["# lambert's built-in Cornell box, written by bench/default_method_bench.py for RenderPark", ""]
    emitted = {}
    for m in scene["materials"]:
        x, y, luminous = mgf_colour(m["albedo"])
        lines += [f"m {name(m['name'])} =", "\tc", f"\t\tcxy {x:.9f} {y:.9f}", f"\trd {luminous:.9f}"]
        if "emittedRadiance" in m:
            emitted[m["name"]] = m["emittedRadiance"]
            x, y, luminous = mgf_colour(m["emittedRadiance"])
            # Radiance L = E / π, E in W/m² = ed / efficacy.
            lines += ["\tc", f"\t\tcxy {x:.9f} {y:.9f}", f"\ted {luminous * math.pi * RPK_WHITE_EFFICACY:.9f}"]
        lines += ["\tsides 1"]
    count = 0
    for s in scene["surfaces"]:
        lines += [f"o {name(s['name'])}", f"m {name(s['material'])}"]
        corners = []
        for v in s["vertices"]:
            count += 1
            lines += [f"v v{count} =", "\tp " + " ".join(f"{x * metres:.9g}" for x in v)]
            corners.append(f"v{count}")
        lines += ["f " + " ".join(corners), "o"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return emitted, metres


def vrml_numbers(text, key):
    start = text.index("[", text.index(key)) + 1
    return text[start:text.index("]", start)].replace(",", " ").split()


def read_renderpark_vrml(path, scale, metres=1.0):
    """RenderPark's VRML (-radiance-model-savefile): every leaf element's corners with its own
    radiance there (its Galerkin basis at the corner), in the MGF's coordinates (turned back into
    the scene's units: / metres), divided by the tone map's scale; each corner's normal is its
    element's (Newell). Rows of lambert's vertex CSV."""
    with open(path) as f:
        text = f.read()
    p = [float(v) for v in vrml_numbers(text, "point [")]
    c = [float(v) for v in vrml_numbers(text, "color [")]
    indices = [int(v) for v in vrml_numbers(text, "coordIndex [")]
    points = [[x / metres for x in p[i:i + 3]] for i in range(0, len(p), 3)]
    colours = [c[i:i + 3] for i in range(0, len(c), 3)]
    if len(points) != len(colours):
        raise RuntimeError(f"{path}: {len(points)} points but {len(colours)} colours")
    normals = [[0.0, 0.0, 0.0] for _ in points]
    polygon = []
    for i in indices + [-1]:
        if i >= 0:
            polygon.append(i)
            continue
        n = [0.0, 0.0, 0.0]
        for k in range(len(polygon)):
            a, b = points[polygon[k]], points[polygon[(k + 1) % len(polygon)]]
            n[0] += (a[1] - b[1]) * (a[2] + b[2])
            n[1] += (a[2] - b[2]) * (a[0] + b[0])
            n[2] += (a[0] - b[0]) * (a[1] + b[1])
        for v in polygon:
            normals[v] = [normals[v][k] + n[k] for k in range(3)]
        polygon = []
    rows = []
    for point, normal, colour in zip(points, normals, colours):
        length = math.sqrt(sum(x * x for x in normal))
        if length == 0:
            continue  # a corner no element uses
        rows.append(point + [x / length for x in normal] + [x / s for x, s in zip(colour, scale)])
    return rows


def averaged_at_shared_corners(references, vertices, samples, scratch):
    """The error when the corners elements share (same point and normal) are averaged on both
    sides, as RenderPark's Gouraud display smooths them: RenderPark's best showing, the error the
    speed ratio is taken at. The averaged reference has more samples per point than the
    per-corner one, so the per-corner noise is an upper bound."""
    reference, _ = references.reference("cornell", vertices, samples)
    header, mine = read_vertices(vertices)
    _, truth = read_vertices(reference)
    groups = {}
    for a, b in zip(mine, truth):
        g = groups.setdefault(tuple(a[:6]), [a[:6], [0.0] * 3, [0.0] * 3, 0])
        g[1] = [x + y for x, y in zip(g[1], a[6:])]
        g[2] = [x + y for x, y in zip(g[2], b[6:])]
        g[3] += 1
    base = os.path.join(scratch, "shared-" + os.path.basename(vertices))
    write_vertices_atomically(base + ".mine.csv", header, [g[0] + [x / g[3] for x in g[1]] for g in groups.values()])
    write_vertices_atomically(base + ".truth.csv", header, [g[0] + [x / g[3] for x in g[2]] for g in groups.values()])
    c = references.compare("cornell", base + ".mine.csv", base + ".truth.csv")
    return {"points": len(groups), "vertex_relative_rmse": round(c["vertex_relative_rmse"], 5), "vertex_bias": round(c["vertex_bias"], 5)}


def renderpark_command(args, mgf, epsilon, iterations, brightness, vrml=None):
    command = [args.renderpark, mgf, "-raytracing-method", "none", "-radiance-method", "Galerkin", "-iterations", str(iterations),
               "-gr-link-error-threshold", f"{epsilon:g}", "-tonemapping", "Ward", "-brightness-adjust", f"{brightness:.6f}"]
    return command + (["-radiance-model-savefile", vrml] if vrml else [])


def renderpark_scale(args, mgf, emitted, scratch):
    """RenderPark's VRML colours are its radiance × a constant of its Ward tone map (linear:
    brightness, efficacy, the display's and the scene's adaptation luminance). After one Jacobi
    iteration the light's corners hold its emitted radiance alone (it sees no emitter), so the
    constant is their colour over lambert's L_e, per channel. The brightness is chosen so the light
    prints near 0.8 (3 significant digits: within 0.06%, and nothing clips at 1)."""
    le = next(iter(emitted.values()))
    brightness = -8.0
    for _ in range(2):
        vrml = os.path.join(scratch, "calibrate.wrl")
        r = run_once(renderpark_command(args, mgf, 1e-5, 1, brightness, vrml), args.timeout, cwd=scratch)
        if r["rc"] != 0 or not os.path.exists(vrml):
            raise RuntimeError(f"RenderPark: {first_error(r)}")
        with open(vrml) as f:
            text = f.read()
        c = [float(v) for v in vrml_numbers(text, "color [")]
        brightest = max((c[i:i + 3] for i in range(0, len(c), 3)), key=lambda v: v[0])
        scale = [brightest[k] / le[k] for k in range(3)]
        if 0.5 < brightest[0] < 0.95:
            break
        brightness += math.log2(0.8 / brightest[0])
    agreement = max(scale) / min(scale) - 1
    if agreement > 0.01:
        raise RuntimeError(f"RenderPark's light is not lambert's colour: scales {scale} differ by {agreement:.2%}")
    return brightness, scale


def renderpark(args, scratch):
    """RenderPark's timed runs and the vertex file of its result at each ε; errors are added by
    renderpark_errors once every timing is taken."""
    if not args.renderpark:
        return {"skipped": "RenderPark is not built beside the project: give --renderpark PATH or $RENDERPARK "
                           "(its `rpk` binary from OscarChavarro/rpkCpp; ../rpk/src/build/rpk is looked for)"}
    if not os.access(args.renderpark, os.X_OK):
        return {"skipped": f"{args.renderpark} is not an executable"}
    folder = os.path.join(args.out, "renderpark")
    os.makedirs(folder, exist_ok=True)
    scene_dir = os.path.join(scratch, "scenes")
    r = run_once([args.lambert, "scenes", "--export", scene_dir], args.timeout)
    if r["rc"] != 0:
        raise RuntimeError(f"lambert scenes --export: {first_error(r)}")
    mgf = os.path.join(folder, "cornell.mgf")
    emitted, metres = write_cornell_mgf(os.path.join(scene_dir, "cornell.json"), mgf)
    brightness, scale = renderpark_scale(args, mgf, emitted, scratch)
    rows = []
    for epsilon in args.renderpark_epsilons:
        command = renderpark_command(args, mgf, epsilon, args.renderpark_iterations, brightness)
        walls, rss = [], []
        for k in range(args.runs):
            log(f"RenderPark ε {epsilon:g}: run {k + 1} of {args.runs}")
            t = run_once(command, args.timeout, cwd=scratch)
            if t["rc"] != 0:
                raise RuntimeError(f"RenderPark: {first_error(t)}")
            walls.append(t["wall"])
            rss.append(t["rss_mib"])
        # The result, from one more run that also writes it (writing VRML every iteration is not
        # timed: RenderPark's times above are its solve alone, which favours it).
        vrml = os.path.join(scratch, f"rpk-{epsilon:g}.wrl")
        w = run_once(renderpark_command(args, mgf, epsilon, args.renderpark_iterations, brightness, vrml), args.timeout, cwd=scratch)
        if w["rc"] != 0:
            raise RuntimeError(f"RenderPark: {first_error(w)}")
        vertices = os.path.join(folder, f"cornell-{epsilon:g}.csv")
        write_vertices_atomically(vertices, "x,y,z,nx,ny,nz,r,g,b", read_renderpark_vrml(vrml, scale, metres))
        rows.append({"epsilon": epsilon, "wall_seconds": spread(walls), "peak_rss_mib": round(max(rss), 1), "vertices_file": vertices})
    return {"binary": args.renderpark, "settings": "-radiance-method Galerkin (hierarchical, clustering, Jacobi, lazy linking: "
            f"its defaults) -iterations {args.renderpark_iterations}, one core",
            "scene": mgf, "brightness_adjust": round(brightness, 6), "tone_map_scale": [round(s, 8) for s in scale], "runs": rows}


def renderpark_errors(args, references, scratch, result, curve):
    """Each ε's error against its reference, the best ε, and lambert's speed ratio there."""
    if "skipped" in result:
        return result
    rows = result["runs"]
    for row in rows:
        row.update(references.error("cornell", row["vertices_file"], args.curve_samples))
        row["shared_corners_averaged"] = averaged_at_shared_corners(references, row["vertices_file"], args.curve_samples, scratch)
    # RenderPark at its best showing: its corners averaged where elements share them, as its own
    # Gouraud display smooths them (per corner, its error is larger and the ratio flattered lambert).
    best = min(rows, key=lambda r: r["shared_corners_averaged"]["vertex_relative_rmse"])
    best_error = best["shared_corners_averaged"]["vertex_relative_rmse"]
    result["best"] = {"epsilon": best["epsilon"], "vertex_relative_rmse": best_error, "per_corner_vertex_relative_rmse": best["vertex_relative_rmse"],
                      "wall_seconds_median": best["wall_seconds"]["median"], "compared": "RenderPark's corners averaged where elements share them"}
    lambert_seconds = interpolate_time(curve, best_error)
    if lambert_seconds is None:
        result["speed_ratio"] = None
        result["speed_ratio_why_not"] = "RenderPark's best error lies outside lambert's curve; widen --curve-link-errors"
    else:
        ratio = best["wall_seconds"]["median"] / lambert_seconds
        result["lambert_wall_seconds_at_that_error"] = round(lambert_seconds, 4)
        result["speed_ratio"] = round(ratio, 3)
        result["target"] = {"name": "renderpark_over_lambert_wall_seconds_at_renderpark_best_error",
                            "min": TARGETS["renderpark_speed_ratio_min"], "value": round(ratio, 3),
                            "target_met": ratio >= TARGETS["renderpark_speed_ratio_min"]}
    return result


def interpolate_time(curve, error):
    """lambert's wall time at a given error: log-log interpolation between the two curve points
    that bracket it (the curve sorted by error); None outside the curve."""
    points = sorted((p["vertex_relative_rmse"], p["wall_seconds"]["median"]) for p in curve)
    for (e0, t0), (e1, t1) in zip(points, points[1:]):
        if e0 <= error <= e1:
            if e1 == e0:
                return min(t0, t1)
            w = math.log(error / e0) / math.log(e1 / e0)
            return math.exp(math.log(t0) + w * (math.log(t1) - math.log(t0)))
    if points and points[0][0] == error:
        return points[0][1]
    return None


# ---------------------------------------------------------------------------------------------
# (c) Buildings, (d) the link cache.

def building_file(args, rooms):
    folder = os.path.join(args.out, "buildings")
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, f"building-{rooms}.json")
    r = run_once([args.lambert, "generate", "building", "--rooms", str(rooms), "--face-size", str(args.face_size), "-o", path],
                 args.timeout)
    if r["rc"] != 0:
        raise RuntimeError(f"lambert generate building: {first_error(r)}")
    return path


def growth(rows, from_faces=1e4):
    """Time ∝ faces^k: k by least squares over every run of every size from about from_faces up
    (log-log; below it a process's fixed start-up cost flattens the curve), with its standard
    error, beside n log n's exponent over the same range; and between consecutive sizes, from the
    medians with the range the runs' min and max allow."""
    fitted = [r for r in rows if r["faces"] >= 0.9 * from_faces]
    fitted = fitted if len(fitted) >= 2 else rows
    xs, ys = [], []
    for row in fitted:
        for t in row["wall_seconds"]["runs"]:
            xs.append(math.log(row["faces"]))
            ys.append(math.log(t))
    result = {"pairs": []}
    for a, b in zip(rows, rows[1:]):
        span = math.log(b["faces"] / a["faces"])
        k = lambda tb, ta: round(math.log(tb / ta) / span, 3)
        result["pairs"].append({"from_faces": a["faces"], "to_faces": b["faces"],
                                "exponent": k(b["wall_seconds"]["median"], a["wall_seconds"]["median"]),
                                "exponent_min": k(b["wall_seconds"]["min"], a["wall_seconds"]["max"]),
                                "exponent_max": k(b["wall_seconds"]["max"], a["wall_seconds"]["min"]),
                                "n_log_n_exponent": round(1 + math.log(math.log(b["faces"]) / math.log(a["faces"])) / span, 3)})
    if len(set(xs)) >= 2:
        mx, my = statistics.fmean(xs), statistics.fmean(ys)
        sxx = sum((x - mx) ** 2 for x in xs)
        slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
        residuals = [y - (my + slope * (x - mx)) for x, y in zip(xs, ys)]
        se = math.sqrt(sum(r * r for r in residuals) / (len(xs) - 2) / sxx) if len(xs) > 2 else None
        first, last = fitted[0]["faces"], fitted[-1]["faces"]
        n_log_n = 1 + math.log(math.log(last) / math.log(first)) / math.log(last / first)
        result["fit"] = {"exponent": round(slope, 3), "standard_error": None if se is None else round(se, 3),
                         "from_faces": first, "to_faces": last, "n_log_n_exponent": round(n_log_n, 3),
                         "target_met": slope <= n_log_n}
    return result


def buildings(args, scratch):
    rows = []
    for rooms in args.rooms:
        scene = building_file(args, rooms)
        output = os.path.join(scratch, f"building-{rooms}-vertices.csv")
        measured, why = timed_runs([args.lambert, "solve", "--scene", scene, "--export-vertices", output, "--json"],
                                   args.runs, args.timeout, scratch, f"building of {rooms} rooms")
        if os.path.exists(output):
            os.remove(output)
        if measured is None:
            rows.append({"rooms": rooms, "error": why})
            continue
        s = measured.pop("stats")
        rows.append({"rooms": rooms, "faces": s.get("faces"), "leaves": s.get("patches"), "links": s.get("links"),
                     "converged": s.get("converged"), **measured})
    good = [r for r in rows if "error" not in r]
    result = {"face_size": args.face_size, "rows": rows, "growth": growth(good)}
    big = [r for r in good if r["faces"] >= 0.5e6]
    if big:
        t, m = big[-1]["wall_seconds"]["median"], big[-1]["peak_rss_mib"]
        limits = TARGETS["building_1e6"]
        result["targets"] = [{"name": "wall_seconds_median_at_1e6_faces", "max": limits["wall_seconds_max"], "value": t,
                              "target_met": t < limits["wall_seconds_max"]},
                             {"name": "peak_rss_mib_at_1e6_faces", "max": limits["peak_rss_mib_max"], "value": m,
                              "target_met": m < limits["peak_rss_mib_max"]}]
    return result


def cache_fields(stats):
    return {k: v for k, v in stats.items() if "cache" in k}


def link_cache(args, scratch):
    scene = building_file(args, args.cache_rooms)
    firsts, seconds, fields = [], [], {}
    for k in range(args.runs):
        cache = tempfile.mkdtemp(prefix="links-", dir=scratch)
        output = os.path.join(scratch, "link-cache-vertices.csv")
        # --method hierarchical: a cache option must never choose the method.
        command = [args.lambert, "solve", "--scene", scene, "--method", "hierarchical", "--cache-dir", cache,
                   "--export-vertices", output, "--json"]
        pair = []
        for which in ("first", "second"):
            log(f"link cache: {which} run, pair {k + 1} of {args.runs}")
            r = run_once(command, args.timeout)
            if r["rc"] != 0:
                shutil.rmtree(cache, ignore_errors=True)
                return {"rooms": args.cache_rooms, "available": False, "why": f"not available: {first_error(r)}"}
            stats = json.loads(r["out"])
            if not str(stats.get("mesh", "")).startswith("hierarchical"):
                return {"rooms": args.cache_rooms, "available": False,
                        "why": f"not available: --cache-dir chose the {stats.get('mesh')} method"}
            if not cache_fields(stats):
                return {"rooms": args.cache_rooms, "available": False, "why": "not available: the solve's JSON reports no link cache"}
            fields[which] = cache_fields(stats)
            pair.append(r["wall"])
            faces = stats.get("faces")
        shutil.rmtree(cache, ignore_errors=True)
        firsts.append(pair[0])
        seconds.append(pair[1])
    ratio = statistics.median(firsts) / statistics.median(seconds)
    return {"rooms": args.cache_rooms, "faces": faces, "available": True, "first_wall_seconds": spread(firsts),
            "second_wall_seconds": spread(seconds), "cache_stats": fields, "speedup": round(ratio, 3),
            "target": {"name": "first_over_second_wall_seconds", "min": TARGETS["link_cache_speedup_min"], "value": round(ratio, 3),
                       "target_met": ratio >= TARGETS["link_cache_speedup_min"]}}


# ---------------------------------------------------------------------------------------------

def beside_project(relative):
    """relative beside the repository (../relative), or beside the main checkout when this is a
    worktree one level further down (../../relative); "" when neither exists."""
    for parent in (os.path.dirname(ROOT), os.path.dirname(os.path.dirname(ROOT))):
        if os.path.exists(os.path.join(parent, relative)):
            return os.path.join(parent, relative)
    return ""


def checkpoint(args, doc):
    """The document so far, in OUT/partial.json (atomically): what a long run has measured when it is stopped."""
    fd, temporary = tempfile.mkstemp(prefix=".tmp-", suffix=".json", dir=args.out)
    with os.fdopen(fd, "w") as f:
        json.dump(doc, f, indent=1)
    os.replace(temporary, os.path.join(args.out, "partial.json"))


def number_list(kind):
    return lambda text: [kind(v) for v in text.split(",") if v]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lambert", default=os.path.join(ROOT, "build/bin/lambert"))
    parser.add_argument("--vertex-reference", default=os.path.join(ROOT, "build/bin/vertex_reference"))
    parser.add_argument("--out", default=os.path.join(ROOT, "out/bench/default_method"),
                        help="vertex files, the MGF, generated buildings and the reference cache")
    parser.add_argument("--runs", type=int, default=3, help="runs per timing (medians, min and max)")
    parser.add_argument("--quick", action="store_true",
                        help="seconds, for CI: 1 run, 256-sample references, link error 1e-4 as the quality setting, "
                             "RenderPark at ε 1e-4 only, the 1-room building only")
    parser.add_argument("--quality-link-error", type=float, default=None,
                        help="the Cornell box's quality setting (default 1e-5; 1e-4 with --quick)")
    parser.add_argument("--reference-samples", type=int, default=32768,
                        help="samples a vertex of the Cornell references (noise about 2.7%% × √(1024 / samples))")
    parser.add_argument("--curve-link-errors", type=number_list(float), default=[3e-3, 1e-3, 5e-4, DEFAULT_LINK_ERROR, 1e-4, 5e-5, 2e-5, 1e-5],
                        help="lambert's time-against-error curve for the comparison with RenderPark (coarser than the "
                             "default too: RenderPark's best error, about 9%%, is above lambert's default's)")
    parser.add_argument("--curve-samples", type=int, default=8192,
                        help="samples a vertex of the curve's and RenderPark's references (errors there are ~5%%)")
    parser.add_argument("--renderpark", default=os.environ.get("RENDERPARK") or beside_project("rpk/src/build/rpk"),
                        help="RenderPark's rpk binary (default $RENDERPARK, else ../rpk/src/build/rpk beside the repository)")
    parser.add_argument("--renderpark-epsilons", type=number_list(float), default=[1e-4, 1e-5, 1e-6])
    parser.add_argument("--renderpark-iterations", type=int, default=11,
                        help="RenderPark's Jacobi iterations (it has no stopping test; its error at ε 1e-5 is the same to "
                             "4 digits at 11, 20, 30 and 60, and 11 is what its own scripts use)")
    parser.add_argument("--rooms", type=number_list(int), default=[1, 8, 64, 640],
                        help="building sizes: 1, 8, 64, 640 rooms are about 2e3, 1.7e4, 1.1e5, 1.1e6 faces")
    parser.add_argument("--no-million", action="store_true", help="leave out buildings of more than 100 rooms (10^6 faces)")
    parser.add_argument("--face-size", type=float, default=0.25)
    parser.add_argument("--cache-rooms", type=int, default=64, help="the link-cache case's building (64 rooms: 10^5 faces)")
    parser.add_argument("--timeout", type=float, default=900, help="seconds per lambert or RenderPark run")
    args = parser.parse_args()
    if args.quick:
        args.runs, args.reference_samples, args.curve_samples = 1, 256, 256
        args.curve_link_errors, args.rooms, args.cache_rooms = [DEFAULT_LINK_ERROR], [1], 1
        args.renderpark_epsilons = [1e-4]
    if args.quality_link_error is None:
        args.quality_link_error = 1e-4 if args.quick else 1e-5
    if args.no_million:
        args.rooms = [r for r in args.rooms if r <= 100]
    for tool in (args.lambert, args.vertex_reference):
        if not os.access(tool, os.X_OK):
            log(f"{tool} is not built: build the lambert_cli and vertex_reference targets (make build)")
            return 2
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    started = time.monotonic()
    doc = {"machine": machine(), "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "load_average_at_start": os.getloadavg(), "quick": args.quick, "runs": args.runs,
           "how": "whole process wall time of the lambert CLI (start to written output), median of runs with min and max; "
                  "peak RSS of the child (wait4); errors: per-vertex relative RMSE against the path tracer at the "
                  "solution's own vertices (lambert compare), beside the reference's own noise"}
    with tempfile.TemporaryDirectory(prefix="default-method-bench-") as scratch:
        # Every timing first, then the references (minutes of tracing, cached): a run stopped
        # early has its times in OUT/partial.json.
        points = {DEFAULT_LINK_ERROR: ("default", []), args.quality_link_error: ("quality", ["--link-error", f"{args.quality_link_error:g}"])}
        for link_error in args.curve_link_errors:
            points.setdefault(link_error, (f"link-error-{link_error:g}", ["--link-error", f"{link_error:g}"]))
        rows = {e: solve_cornell(args, scratch, name, options, args.runs) for e, (name, options) in points.items()}
        doc["cornell"] = {"default": rows[DEFAULT_LINK_ERROR], "quality": rows[args.quality_link_error]}
        checkpoint(args, doc)
        doc["renderpark"] = renderpark(args, scratch)
        checkpoint(args, doc)
        doc["building"] = buildings(args, scratch)
        checkpoint(args, doc)
        doc["link_cache"] = link_cache(args, scratch)
        checkpoint(args, doc)

        references = References(args, scratch)
        with_target(measure_error(references, rows[DEFAULT_LINK_ERROR], args.reference_samples), TARGETS["cornell_default"])
        with_target(measure_error(references, rows[args.quality_link_error], args.reference_samples), TARGETS["cornell_quality"])
        checkpoint(args, doc)
        curve = []
        for link_error in args.curve_link_errors:
            point = rows[link_error]
            if "vertex_relative_rmse" not in point:
                measure_error(references, point, args.curve_samples)
            curve.append({"link_error": link_error, "wall_seconds": point["wall_seconds"], "vertex_relative_rmse": point["vertex_relative_rmse"],
                          "reference_noise": point["reference_noise"], "leaves": point["leaves"], "links": point["links"]})
        doc["cornell"]["curve"] = curve
        checkpoint(args, doc)
        renderpark_errors(args, references, scratch, doc["renderpark"], curve)
    doc["load_average_at_end"] = os.getloadavg()
    doc["bench_seconds"] = round(time.monotonic() - started, 1)
    json.dump(doc, sys.stdout, indent=1)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
