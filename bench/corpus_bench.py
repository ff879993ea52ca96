#!/usr/bin/env python3
"""The real-scene corpus benchmark: every third-party scene of bench/corpus/manifest.json, as a user runs it.

For each scene that scripts/fetch-corpus.py could bring (the others are listed with the reason
they were skipped) it runs `lambert render --scene FILE --json -o OUT/<id>.png` with the
manifest's camera (`--eye/--target/--up/--fov`, in the file's own frame; "file" uses the file's
camera, "default" lambert's own choice), the manifest's "options" (only `--sides one` where
RenderPark's own script forces faces one-sided) and default options otherwise, and reports:
loaded, faces, links, whether the solve converged, the whole process's wall time (process start
to written PNG) and peak resident memory, and whether the picture is usable: neither black (under a
quarter of its pixels lit, or their median luminance under 8 of 255) nor blown out (over 10% of
its pixels white: lamps in view are); the 1st, 50th and 99th percentiles of the lit pixels' luminance are reported.
With --atlas-bench (build/bin/atlas_bench), each scene's lightmap atlas at 1024² is packed too
(charts, atlases, packing efficiency).

Where RenderPark is built beside lambert (--renderpark PATH, or $RENDERPARK), each MGF scene is
also run through it with the settings its own scripts use, as an external program, and its wall
time is reported beside lambert's (RenderPark is GPL: it is run, never linked or copied).

Every lambert run is `--no-cache` (a user's first run), so the final gather's time against
everything before the picture (`gather_over_solve`) compares work done in that run alone.

The picture target (issue "a picture as fast as the solve"): RenderPark's hospital as its files
have it (two-sided), lambert's default view, `render --width 256 --height 256 --no-cache`, the
median of at least 3 whole processes, against 6 s; and how many scenes' pictures gather in at most
the time before them.

Prints one JSON document on stdout; progress on stderr. `--runs 3` gives medians of 3 runs.

    bench/corpus_bench.py [--lambert build/bin/lambert] [--corpus real-scenes] [--out out/bench/corpus]
                          [--renderpark PATH] [--runs N] [--only ID,ID] [--timeout SECONDS]
                          [--atlas-bench build/bin/atlas_bench]
"""
import argparse
import json
import os
import platform
import statistics
import struct
import subprocess
import sys
import time
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def log(message):
    print(f"corpus_bench: {message}", file=sys.stderr, flush=True)


def read_png_rgb(path):
    """Decodes an 8-bit RGB or RGBA, non-interlaced PNG (what lambert writes): (width, height, rows of bytes)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    offset, idat, width = 8, b"", 0
    while offset < len(data):
        length, kind = struct.unpack(">I4s", data[offset:offset + 8])
        body = data[offset + 8:offset + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise ValueError(f"{path}: only 8-bit RGB(A) non-interlaced PNGs are read here")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        offset += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        filter_type = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            upper_left = previous[i - channels] if i >= channels else 0
            if filter_type == 1:
                line[i] = (line[i] + left) & 255
            elif filter_type == 2:
                line[i] = (line[i] + up) & 255
            elif filter_type == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif filter_type == 4:
                p = left + up - upper_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - upper_left)
                predictor = left if pa <= pb and pa <= pc else (up if pb <= pc else upper_left)
                line[i] = (line[i] + predictor) & 255
        rows.append(bytes(line[i] for i in range(stride) if i % channels < 3) if channels == 4 else bytes(line))
        previous = line
    return width, height, rows


def picture_statistics(path):
    """Luminance (Rec. 709 weights on the 8-bit sRGB values, 0–255) of a PNG's pixels: the share of
    pixels that are not pure black (what shows a lit surface: black is the background, a back face
    or an unlit surface), the 1st, 50th and 99th percentiles over those, and the share at white."""
    _, _, rows = read_png_rgb(path)
    values = [0.2126 * row[i] + 0.7152 * row[i + 1] + 0.0722 * row[i + 2] for row in rows for i in range(0, len(row), 3)]
    lit = sorted(v for v in values if v > 0)
    pick = lambda q: lit[min(len(lit) - 1, int(q * len(lit)))] if lit else 0.0
    return {"lit_share": len(lit) / len(values), "p1": pick(0.01), "p50": pick(0.5), "p99": pick(0.99),
            "white_share": sum(1 for v in values if v >= 254.5) / len(values)}


def usable(picture):
    """Neither black (under a quarter of the pixels lit, or their median under 8/255) nor blown
    out (more than 10% of all pixels at white: a lamp in view is white, a wall should not be)."""
    return picture["lit_share"] >= 0.25 and picture["p50"] >= 8 and picture["white_share"] <= 0.10


def run_in_fresh_interpreter(command, timeout, cwd=None):
    """Runs the command under a fresh Python so RUSAGE_CHILDREN holds this run alone."""
    probe = ("import json,resource,subprocess,sys,time\n"
             "start=time.monotonic()\n"
             "p=subprocess.run(json.loads(sys.argv[1]),capture_output=True,timeout=float(sys.argv[2]))\n"
             "wall=time.monotonic()-start\n"
             "rss=resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss/1024\n"
             "sys.stdout.write(json.dumps({'rc':p.returncode,'wall':wall,'rss':rss,"
             "'out':p.stdout.decode(errors='replace'),'err':p.stderr.decode(errors='replace')}))\n")
    try:
        result = subprocess.run([sys.executable, "-c", probe, json.dumps(command), str(timeout)],
                                capture_output=True, timeout=timeout + 30, cwd=cwd)
        measured = json.loads(result.stdout)
    except (subprocess.TimeoutExpired, ValueError):
        return {"rc": None, "wall": float(timeout), "rss": None, "out": "", "err": f"timed out after {timeout} s"}
    return measured


def first_error(stderr):
    lines = stderr.strip().splitlines()
    return next((line for line in lines if "error" in line.lower()), lines[0] if lines else "no message")


# RenderPark's hospital, two-sided as its files are, at lambert's default view.
PICTURE_TARGET = {"id": "rpk-hospital", "width": 256, "height": 256, "wall_seconds_max": 6.0}


def picture_target(args, ready):
    scene = ready.get(PICTURE_TARGET["id"], {"status": "skipped", "reason": "not in the fetch report"})
    if scene["status"] != "ready":
        return {"id": PICTURE_TARGET["id"], "skipped": scene["reason"]}
    image = os.path.join(args.out, "hospital-default-view.png")
    command = [args.lambert, "render", "--scene", scene["path"], "--no-cache", "--width", str(PICTURE_TARGET["width"]),
               "--height", str(PICTURE_TARGET["height"]), "--json", "-o", image]
    runs = []
    for run in range(max(3, args.runs)):
        log(f"picture target: {PICTURE_TARGET['id']} run {run + 1}")
        runs.append(run_in_fresh_interpreter(command, args.timeout))
    if any(r["rc"] != 0 for r in runs):
        return {"id": PICTURE_TARGET["id"], "error": first_error(next(r for r in runs if r["rc"] != 0)["err"])}
    walls = [r["wall"] for r in runs]
    stats = json.loads(runs[-1]["out"])
    median = statistics.median(walls)
    return {"id": PICTURE_TARGET["id"], "command": " ".join(command[1:]), "wall_seconds_median": round(median, 3),
            "wall_seconds_runs": [round(w, 3) for w in walls], "peak_rss_mib": max(r["rss"] for r in runs),
            **{k: stats.get(k) for k in ("gather_vertices", "vertices", "gather_seconds", "link_seconds", "solve_seconds")},
            "target": {"wall_seconds_max": PICTURE_TARGET["wall_seconds_max"],
                       "target_met": median < PICTURE_TARGET["wall_seconds_max"]}}


def camera_arguments(camera):
    if camera in (None, "file", "default"):
        return []
    arguments = ["--eye", ",".join(map(str, camera["eye"])), "--target", ",".join(map(str, camera["target"]))]
    if "up" in camera:
        arguments += ["--up", ",".join(map(str, camera["up"]))]
    if "fov" in camera:
        arguments += ["--fov", str(camera["fov"])]
    return arguments


def machine():
    model = platform.processor()
    try:
        with open("/proc/cpuinfo") as f:
            model = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), model)
    except OSError:
        pass
    return {"cpu": model, "threads": os.cpu_count(), "load_average_at_start": os.getloadavg()[0]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lambert", default=os.path.join(ROOT, "build/bin/lambert"))
    parser.add_argument("--manifest", default=os.path.join(ROOT, "bench/corpus/manifest.json"))
    parser.add_argument("--corpus", default=os.path.join(ROOT, "real-scenes"))
    parser.add_argument("--out", default=os.path.join(ROOT, "out/bench/corpus"))
    parser.add_argument("--renderpark", default=os.environ.get("RENDERPARK", ""))
    parser.add_argument("--runs", type=int, default=1)
    parser.add_argument("--only", default="", help="comma-separated scene ids")
    parser.add_argument("--timeout", type=float, default=900, help="seconds per run")
    parser.add_argument("--atlas-bench", default="", help="atlas_bench binary: also pack each scene's lightmap atlas (1024²)")
    args = parser.parse_args()

    fetched = subprocess.run([sys.executable, os.path.join(ROOT, "scripts/fetch-corpus.py"),
                              "--manifest", args.manifest, "--out", args.corpus],
                             capture_output=True, text=True)
    sys.stderr.write(fetched.stderr)
    ready = {s["id"]: s for s in json.loads(fetched.stdout)["scenes"]}
    with open(args.manifest) as f:
        manifest = json.load(f)
    os.makedirs(args.out, exist_ok=True)
    only = set(filter(None, args.only.split(",")))
    renderpark = args.renderpark if args.renderpark and os.access(args.renderpark, os.X_OK) else ""
    if not renderpark:
        log("RenderPark: not run (give --renderpark PATH or $RENDERPARK: its `rpk` binary, built from "
            "OscarChavarro/rpkCpp beside lambert)")

    rows = []
    for scene in manifest["scenes"]:
        if only and scene["id"] not in only:
            continue
        row = {"id": scene["id"], "format": scene["format"], "source": manifest["sources"][scene["source"]].get("repo", "this repository")}
        fetched_scene = ready.get(scene["id"], {"status": "skipped", "reason": "not in the fetch report"})
        if fetched_scene["status"] != "ready":
            row.update(loaded=False, skipped=fetched_scene["reason"])
            rows.append(row)
            continue
        path = fetched_scene["path"]
        loaded = run_in_fresh_interpreter([args.lambert, "info", "--scene", path, "--json"], args.timeout)
        row["loaded"] = loaded["rc"] == 0
        if not row["loaded"]:
            row["error"] = first_error(loaded["err"])
            rows.append(row)
            continue
        row["load_seconds"] = loaded["wall"]
        if args.atlas_bench:
            packed = run_in_fresh_interpreter([args.atlas_bench, "--sizes", "1024", "--only-named", path], args.timeout)
            try:
                atlas = next(r for r in json.loads(packed["out"])["scenes"] if r["scene"] == path)
                row["lightmap_atlas"] = {k: atlas[k] for k in ("origin", "charts", "atlases", "efficiency", "seconds", "error") if k in atlas}
            except (ValueError, StopIteration, KeyError):
                row["lightmap_atlas"] = {"error": first_error(packed["err"])}
        image = os.path.join(args.out, scene["id"] + ".png")
        command = ([args.lambert, "render", "--scene", path, "--no-cache", "--json", "-o", image] + camera_arguments(scene.get("camera")) +
                   scene.get("options", []))
        row["camera"] = scene.get("camera", "file")
        row["options"] = " ".join(scene.get("options", []))
        runs = []
        for run in range(args.runs):
            log(f"{scene['id']}: lambert run {run + 1} of {args.runs}")
            runs.append(run_in_fresh_interpreter(command, args.timeout))
        last = runs[-1]
        row["exit_status"] = last["rc"]
        stats = {}
        try:
            stats = json.loads(last["out"]) if last["rc"] == 0 else {}
        except ValueError:
            pass
        if last["rc"] != 0:
            row["error"] = first_error(last["err"])
        walls = [r["wall"] for r in runs]
        row["wall_seconds_median"] = statistics.median(walls)
        row["wall_seconds_runs"] = walls
        row["peak_rss_mib"] = max((r["rss"] for r in runs if r["rss"] is not None), default=None)
        for key in ("faces", "elements", "links", "converged", "iterations", "residual", "emitted_watts", "exposure_stops",
                    "inject_seconds", "light_edge_seconds", "link_seconds", "solve_seconds", "gather_seconds", "render_seconds",
                    "total_seconds"):
            if key in stats:
                row[key] = stats[key]
        if "gather_seconds" in stats and "render_seconds" in stats and "total_seconds" in stats:
            # The final gather against everything before the picture (load, links, solve): issue
            # "a picture as fast as the solve" asks for at most 1.
            before = stats["total_seconds"] - stats["render_seconds"]
            row["gather_over_solve"] = round(stats["gather_seconds"] / max(before, 1e-9), 3)
        if "inject_seconds" in stats:  # the lights' direct light (a sky's most of all): its share of the process
            row["inject_share_of_wall"] = round(stats["inject_seconds"] / max(row["wall_seconds_median"], 1e-9), 3)
        row["warnings"] = len(stats.get("warnings", []))
        if last["rc"] == 0 and os.path.exists(image):
            picture = picture_statistics(image)
            row["picture_statistics"] = {k: round(v, 3) for k, v in picture.items()}
            row["picture_usable"] = usable(picture)
            row["picture"] = os.path.relpath(image, ROOT)
        if renderpark and scene["format"] == "mgf" and "renderpark" in scene:
            source_root = os.path.join(args.corpus, scene["source"])
            rpk_walls = []
            for run in range(args.runs):
                log(f"{scene['id']}: RenderPark run {run + 1} of {args.runs}")
                measured = run_in_fresh_interpreter([renderpark, scene["file"]] + scene["renderpark"], args.timeout, cwd=source_root)
                rpk_walls.append(measured["wall"] if measured["rc"] == 0 else None)
            if all(w is not None for w in rpk_walls):
                row["renderpark_wall_seconds_median"] = statistics.median(rpk_walls)
                row["renderpark_settings"] = " ".join(scene["renderpark"])
            else:
                row["renderpark_failed"] = True
        rows.append(row)
        log(f"{scene['id']}: " + json.dumps({k: row.get(k) for k in ("exit_status", "faces", "links", "converged",
                                                                          "wall_seconds_median", "peak_rss_mib",
                                                                          "picture_statistics", "picture_usable", "renderpark_wall_seconds_median")}))

    tried = [r for r in rows if "skipped" not in r]
    summary = {
        "scenes": len(rows),
        "tried": len(tried),
        "skipped": len(rows) - len(tried),
        "rendered": sum(1 for r in tried if r.get("exit_status") == 0),
        "converged": sum(1 for r in tried if r.get("converged") == "yes"),
        "pictures_usable": sum(1 for r in tried if r.get("picture_usable")),
        "gather_at_most_solve": sum(1 for r in tried if r.get("gather_over_solve", 2) <= 1),
        "gather_measured": sum(1 for r in tried if "gather_over_solve" in r),
    }
    if not only or PICTURE_TARGET["id"] in only:
        summary["picture_target"] = picture_target(args, ready)
    json.dump({"machine": machine(), "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
               "runs_per_scene": args.runs, "summary": summary, "scenes": rows}, sys.stdout, indent=1)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
