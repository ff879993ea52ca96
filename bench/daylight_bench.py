#!/usr/bin/env python3
"""A year of daylight in a minute: `lambert daylight` on the daylit office (scenes/daylight/, its window
facing north as the file has it) on a 0.6 m work plane at 0.8 m, 8,760 hours to sDA, ASE and UDI, as
whole processes (start to written CSV and plans), --runs times each, medians:

  year       the synthetic year (tests/weather/make_test_epw.py --year: Boulder's sun, the test week's
             seven kinds of sky in turn), the coefficients computed (--no-cache)
  cached     the same, the coefficients read from the cache written by a first run
  corpus     each fetched weather file of bench/corpus/manifest.json's "ladybug-weather" (real-scenes/),
             where there is one
  direct     one hour solved directly (`lambert solve` of office-clear.json, a clear sky and a sun,
             measured on the same work plane): × the year's daylit hours, what hour-by-hour solves
             would cost

Target (issue 45): the year under 60 s and 2 GB on the 2-core machine, the coefficient phase apart.
With --carpet PNG, draws the hourly illuminance at the room's middle sensor over the year (days across,
hours down; a "carpet plot") from --hourly's CSV. Prints one JSON document; progress on stderr.

    bench/daylight_bench.py [--lambert build/bin/lambert] [--runs 3] [--out out/bench/daylight] [--carpet PNG]
"""
import argparse
import csv
import glob
import json
import os
import resource
import statistics
import struct
import subprocess
import sys
import time
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "daylight", "office-overcast.json")


def log(message):
    print(f"daylight_bench: {message}", file=sys.stderr, flush=True)


def run(command):
    """Wall seconds, the child's peak RSS (bytes) and its JSON."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    start = time.monotonic()
    r = subprocess.run(command, capture_output=True, text=True, timeout=900)
    wall = time.monotonic() - start
    if r.returncode != 0:
        raise SystemExit(f"daylight_bench: {' '.join(command)} failed:\n{r.stderr}")
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return wall, max(peak, before) * 1024, json.loads(r.stdout)


def median_runs(command, runs):
    walls, peaks, last = [], [], None
    for _ in range(runs):
        wall, peak, last = run(command)
        walls.append(wall)
        peaks.append(peak)
    return {"seconds_median": statistics.median(walls), "seconds": walls, "peak_rss_bytes_max": max(peaks),
            "coefficient_seconds": last.get("coefficient_seconds"), "hourly_seconds": last.get("hourly_seconds"),
            "sensors": last.get("sensors"), "hours": last.get("hours"), "daylight_hours": last.get("daylight_hours"),
            "sda_percent": last.get("sda_percent"), "ase_percent": last.get("ase_percent"),
            "udi_useful_percent": last.get("udi_useful_percent"), "basis_suns": last.get("basis_suns")}


def write_png(path, width, height, rgb):
    rows = b"".join(b"\x00" + bytes(rgb[y * width * 3:(y + 1) * width * 3]) for y in range(height))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def carpet(hourly_csv, png):
    """Days across (365), hours down (24, midnight at the top), the middle sensor's lux on a log scale
    from 10 to 10,000 lx, black below; each cell 2 × 8 pixels."""
    with open(hourly_csv) as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    sensors = len(header) - 3
    column = 3 + sensors // 2
    cell_w, cell_h = 2, 8
    width, height = 365 * cell_w, 24 * cell_h
    rgb = bytearray(width * height * 3)
    import math
    for i, row in enumerate(rows[:8760]):
        day, hour = i // 24, int(row[2]) - 1
        lux = float(row[column])
        t = 0 if lux < 10 else min(1.0, math.log10(lux / 10) / 3)
        colour = (int(255 * min(1, 2 * t)), int(255 * max(0, min(1, 2 * t - 0.5))), int(255 * max(0, 2 * t - 1))) if lux >= 10 else (0, 0, 0)
        for y in range(hour * cell_h, (hour + 1) * cell_h):
            for x in range(day * cell_w, (day + 1) * cell_w):
                at = (y * width + x) * 3
                rgb[at:at + 3] = bytes(colour)
    write_png(png, width, height, rgb)
    log(f"wrote {png} (sensor {column - 2} of {sensors})")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lambert", default=os.path.join(ROOT, "build", "bin", "lambert"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "daylight"))
    parser.add_argument("--carpet", default="")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    year = os.path.join(args.out, "synthetic-year.epw")
    with open(year, "w") as f:
        subprocess.run([sys.executable, os.path.join(ROOT, "tests", "weather", "make_test_epw.py"), "--year"], stdout=f, check=True)
    common = ["daylight", "--scene", SCENE, "--work-plane", "0.8", "--grid-spacing", "0.6", "--json"]
    report = {"scene": "scenes/daylight/office-overcast.json", "grid_spacing_metres": 0.6, "target_seconds": 60,
              "target_peak_rss_bytes": 2 * 1024 ** 3}
    log("the synthetic year, coefficients computed")
    report["year"] = median_runs([args.lambert] + common + ["--weather", year, "--no-cache", "-o", os.path.join(args.out, "year"),
                                                            "--hourly", os.path.join(args.out, "year-hourly.csv")], args.runs)
    cache = os.path.join(args.out, "cache")
    run([args.lambert] + common + ["--weather", year, "--cache-dir", cache])
    log("the synthetic year, coefficients cached")
    report["cached"] = median_runs([args.lambert] + common + ["--weather", year, "--cache-dir", cache], args.runs)
    report["corpus"] = {}
    for epw in sorted(glob.glob(os.path.join(ROOT, "real-scenes", "ladybug-weather", "**", "*.epw"), recursive=True)):
        log(f"{os.path.basename(epw)}")
        report["corpus"][os.path.basename(epw)] = median_runs([args.lambert] + common + ["--weather", epw, "--no-cache"], args.runs)
    log("one hour solved directly")
    direct = [args.lambert, "solve", "--scene", os.path.join(ROOT, "scenes", "daylight", "office-clear.json"), "--no-cache",
              "--work-plane", "0.8", "--grid-spacing", "0.6", "--json"]
    walls = [run(direct)[0] for _ in range(args.runs)]
    hours = report["year"]["daylight_hours"] or 0
    report["direct_hour"] = {"seconds_median": statistics.median(walls), "seconds": walls,
                             "year_estimate_seconds": statistics.median(walls) * hours}
    report["year"]["meets_target"] = report["year"]["seconds_median"] < 60 and report["year"]["peak_rss_bytes_max"] < 2 * 1024 ** 3
    report["speedup_over_hourly_solves"] = report["direct_hour"]["year_estimate_seconds"] / report["year"]["seconds_median"]
    if args.carpet:
        carpet(os.path.join(args.out, "year-hourly.csv"), args.carpet)
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
