#!/usr/bin/env python3
"""Runs two lambert binaries over the same outputs and says whether every file is byte-identical.

For a change meant to leave behaviour alone (a reorganisation, a rename, a faster path that must
give the same bits): build the old commit beside the new one and give both binaries. Each output
a user consumes is written by both (vertex files, glb with vertex colours and with lightmaps,
lightmap EXRs, PNG and EXR pictures, lux at points, on grids and work planes, probes, the link
cache written and read again) on the shipped scenes and, with --corpus, on every scene of the
third-party corpus (scripts/fetch-corpus.py) as a vertex file. What differs by design is left
out: times (the stats' and the report's), the output folder's own path, and the link cache's file
names (keyed by a digest of the sources, so any change to them renames the files; what the cache
gives back is compared, as the second solve's vertices). Prints one line per output and a
summary; exit 1 when any output differs or either binary fails where the other did not.

    scripts/compare-outputs.py --before OLD/bin/lambert --after build/bin/lambert [--corpus real-scenes]
"""
import argparse
import filecmp
import json
import re
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent

# (name, arguments after the binary); OUT/ is replaced by each binary's own output folder.
SHIPPED = [
    ("cornell-default", ["solve", "--scene", "cornell", "--no-cache", "--export-vertices", "OUT/v.csv", "--export", "OUT/c.glb", "--json"]),
    ("cornell-flat", ["solve", "--scene", "cornell", "--method", "flat", "--no-cache", "--export-vertices", "OUT/v.ply"]),
    ("cornell-adaptive", ["solve", "--scene", "cornell", "--adaptive", "--no-cache", "--export-vertices", "OUT/v.csv"]),
    ("cornell-shoot", ["solve", "--scene", "cornell", "--method", "flat", "--solver", "shoot", "--no-cache", "--export-vertices", "OUT/v.csv"]),
    ("cornell-render", ["render", "--scene", "cornell", "--no-cache", "--width", "160", "--height", "160", "-o", "OUT/c.png"]),
    ("cornell-render-exr", ["render", "--scene", "cornell", "--no-cache", "--width", "96", "--height", "96", "-o", "OUT/c.exr"]),
    ("cornell-spots", ["solve", "--scene", "scenes/cornell/cornell-spots.json", "--no-cache", "--export-vertices", "OUT/v.csv"]),
    ("cornell-obj", ["render", "--scene", "scenes/cornell/cornell-obj.json", "--no-cache", "--width", "128", "--height", "128", "-o", "OUT/c.png"]),
    ("cornell-lightmaps", ["solve", "--scene", "scenes/cornell/cornell.json", "--no-cache", "--lightmaps", "--lightmap-size", "128",
                           "--export", "OUT/lm.glb", "--image", "OUT/lm.png", "--width", "128", "--height", "128"]),
    ("cornell-probes", ["solve", "--scene", "cornell", "--no-cache", "--probes", "OUT/probes.json"]),
    ("cornell-link-cache", ["solve", "--scene", "cornell", "--cache-dir", "OUT/cache", "--export-vertices", "OUT/first.csv"]),
    ("cornell-link-cache-read", ["solve", "--scene", "cornell", "--cache-dir", "OUT/cache", "--export-vertices", "OUT/second.csv"]),
    ("office-lit", ["solve", "--scene", "scenes/daylight/office-lit.json", "--no-cache", "--export-vertices", "OUT/v.csv",
                    "--work-plane", "0.8", "--export-grids", "OUT/grid-", "--points", "POINTS", "--export-points", "OUT/points.csv"]),
    ("office-overcast", ["solve", "--scene", "scenes/daylight/office-overcast.json", "--no-cache", "--export-vertices", "OUT/v.csv"]),
    ("office-clear-render", ["render", "--scene", "scenes/daylight/office-clear.json", "--no-cache", "--width", "128", "--height", "96", "-o", "OUT/o.png"]),
    ("floor", ["solve", "--scene", "scenes/floor/floor.json", "--no-cache", "--export-vertices", "OUT/v.csv"]),
    ("room-gltf", ["solve", "--scene", "scenes/room/room.gltf", "--no-cache", "--export-vertices", "OUT/v.csv", "--export", "OUT/r.glb"]),
    ("report", ["report", "--scene", "scenes/daylight/office-lit.json", "--no-cache", "-o", "OUT/report.html"]),
]

TIMED_ROW = re.compile(r'class="name">[^<]*\btime\b')
POINTS = "x,y,z,nx,ny,nz\n1,0.8,1,0,1,0\n2,0.8,2,0,1,0\n3,0.8,1.5,0,1,0\n"


def corpus_runs(corpus):
    manifest = json.loads((ROOT / "bench" / "corpus" / "manifest.json").read_text())
    runs = []
    for scene in manifest["scenes"]:
        path = pathlib.Path(corpus) / scene["source"] / scene["file"] if "source" in scene else None
        if path is None or not path.exists():
            continue
        name = "corpus-" + scene.get("id", path.stem)
        runs.append((name, ["solve", "--scene", str(path), "--no-cache", "--export-vertices", "OUT/v.csv"] + scene.get("options", [])))
    return runs


def run_all(binary, runs, folder, points):
    results = {}
    for name, arguments in runs:
        out = folder / name.removesuffix("-read")
        out.mkdir(parents=True, exist_ok=True)
        command = [binary] + [a.replace("OUT", str(out)).replace("POINTS", str(points)) for a in arguments]
        done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
        stdout = done.stdout
        if "--json" in arguments:  # times differ from run to run; the rest of the stats must not
            stats = json.loads(stdout)
            stdout = json.dumps({k: v for k, v in stats.items() if "seconds" not in k and "time" not in k}, sort_keys=True)
            stdout = stdout.replace(str(out), "OUT")
        (out / f"{name}.stdout").write_text(stdout if "--json" in arguments else "")
        results[name] = done.returncode
        print(f"  {pathlib.Path(binary).name} {name}: exit {done.returncode}", file=sys.stderr)
    return results


def same(old, new):
    """Byte-identical, but for the report's times (its rows named "… time")."""
    if old.suffix == ".html":
        untimed = lambda path: [line for line in path.read_text().splitlines() if not TIMED_ROW.search(line)]
        return untimed(old) == untimed(new)
    return filecmp.cmp(old, new, shallow=False)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True)
    parser.add_argument("--after", required=True)
    parser.add_argument("--corpus", help="the fetched corpus (scripts/fetch-corpus.py --out DIR)")
    parser.add_argument("--keep", help="keep the outputs in this folder")
    args = parser.parse_args()
    runs = SHIPPED + (corpus_runs(args.corpus) if args.corpus else [])
    work = pathlib.Path(args.keep or tempfile.mkdtemp(prefix="lambert-compare-"))
    points = work / "points.csv"
    work.mkdir(parents=True, exist_ok=True)
    points.write_text(POINTS)
    before = run_all(os.path.abspath(args.before), runs, work / "before", points)
    after = run_all(os.path.abspath(args.after), runs, work / "after", points)
    differing, compared = [], 0
    for name, _ in runs:
        if before[name] != after[name]:
            differing.append(f"{name}: exit {before[name]} before, {after[name]} after")
    for old in sorted((work / "before").rglob("*")):
        if not old.is_file() or "cache" in old.relative_to(work / "before").parts:
            continue
        new = work / "after" / old.relative_to(work / "before")
        compared += 1
        if not new.exists():
            differing.append(f"{old.relative_to(work / 'before')}: missing after")
        elif not same(old, new):
            differing.append(f"{old.relative_to(work / 'before')}: differs")
    for line in differing:
        print(f"DIFFERENT {line}")
    print(json.dumps({"runs": len(runs), "files_compared": compared, "different": len(differing), "outputs": str(work)}))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True) if not differing else None
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
