#!/usr/bin/env python3
"""The lightmap bake a Blender user waits for: a small room with Blender's own Lightmap Pack UVs.

bench/blender_room.py builds the room in headless Blender (5 x 4 x 2.7 m, 562 quads, six
emissive ceiling panels, a floor slab whose top lies on the floor, a desk; every object's second
UV layer from Lightmap Pack, exported as TEXCOORD_1) into OUT/blender_room.glb once. Then, --runs
times each, whole processes from start to written file:

  solve      `lambert solve --scene ROOM --no-cache --json`
  lightmaps  `lambert solve --scene ROOM --no-cache --lightmaps --export OUT/room.glb --json` at the
             default texel density (the atlases together hold about one 1024² atlas's texels)

and reports the medians with their spread, the texels baked, the texel size, and the bake's
time over the solve's (issue "a picture as fast as the solve": the room under 10 s, a bake within
2x its solve). Without Blender the room is not made and the report says so.

Prints one JSON document on stdout; progress on stderr.

    bench/lightmap_room_bench.py [--lambert build/bin/lambert] [--blender blender] [--runs 3] [--out out/bench/lightmap_room]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def log(message):
    print(f"lightmap_room_bench: {message}", file=sys.stderr, flush=True)


def timed(command, timeout):
    start = time.monotonic()
    r = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    wall = time.monotonic() - start
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(command)}: exit {r.returncode}: {r.stderr.strip().splitlines()[-1:]}")
    return wall, json.loads(r.stdout)


def spread(values):
    return {"median": round(statistics.median(values), 3), "min": round(min(values), 3), "max": round(max(values), 3),
            "runs": [round(v, 3) for v in values]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lambert", default=os.path.join(ROOT, "build", "bin", "lambert"))
    parser.add_argument("--blender", default=shutil.which("blender") or "")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--timeout", type=float, default=1800)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "lightmap_room"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    room = os.path.join(args.out, "blender_room.glb")
    if not os.path.exists(room):
        if not args.blender:
            print(json.dumps({"available": False, "why": "Blender is not installed: the room is made by Blender's own exporter"}))
            return
        log("making the room in Blender")
        made = subprocess.run([args.blender, "-b", "--factory-startup", "-P", os.path.join(ROOT, "bench", "blender_room.py"), "--",
                               room + ".tmp.glb"], capture_output=True, text=True, timeout=600)
        if made.returncode != 0 or not os.path.exists(room + ".tmp.glb"):
            print(json.dumps({"available": False, "why": "Blender did not make the room: " + made.stderr.strip()[-300:]}))
            return
        os.replace(room + ".tmp.glb", room)
    solves, bakes, stats = [], [], {}
    for run in range(args.runs):
        log(f"solve, run {run + 1} of {args.runs}")
        wall, _ = timed([args.lambert, "solve", "--scene", room, "--no-cache", "--json"], args.timeout)
        solves.append(wall)
        log(f"lightmaps, run {run + 1} of {args.runs}")
        wall, stats = timed([args.lambert, "solve", "--scene", room, "--no-cache", "--lightmaps", "--export",
                             os.path.join(args.out, "room.glb"), "--json"], args.timeout)
        bakes.append(wall)
    result = {
        "available": True,
        "faces": stats.get("faces"),
        "solve_wall_seconds": spread(solves),
        "lightmaps_wall_seconds": spread(bakes),
        "lightmap_atlases": stats.get("lightmap_atlases"),
        "lightmap_size": stats.get("lightmap_size"),
        "lightmap_texel_size_m": stats.get("lightmap_texel_size_m"),
        "lightmap_texels_baked": stats.get("lightmap_texels_baked"),
        "lightmap_bake_seconds": stats.get("lightmap_bake_seconds"),
        "microseconds_per_texel": round(1e6 * stats.get("lightmap_bake_seconds", 0) / max(stats.get("lightmap_texels_baked", 1), 1), 1),
        "bake_over_solve": round(statistics.median(bakes) / max(statistics.median(solves), 1e-9), 1),
        "target_seconds": 10,
    }
    print(json.dumps(result, indent=1))


main()
