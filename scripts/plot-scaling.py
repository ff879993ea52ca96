#!/usr/bin/env python3
"""Log-log plot of the default method's scaling curve (whole-process `lambert solve` time, median of
the runs, and peak memory against faces; bench/default_method_bench.py's "building" rows) as SVG.

    scripts/plot-scaling.py out/bench/default_method.json docs/images/hierarchical-scaling.svg
"""
import json
import math
import sys

def main(source, target):
    rows = [r for r in json.load(open(source))["building"]["rows"] if "error" not in r]
    faces = [r["faces"] for r in rows]
    series = [("time (s, median)", [r["wall_seconds"]["median"] for r in rows], "#c0392b"),
              ("peak memory (GB)", [r["peak_rss_mib"] / 1024 for r in rows], "#2471a3"),
              ("n log n, through the second time", None, "#999999")]
    w, h, left, bottom, top, right = 640, 400, 70, 50, 20, 20
    x0, x1 = math.floor(math.log10(min(faces))), math.ceil(math.log10(max(faces)))
    values = [v for _, s, _ in series if s for v in s]
    y0, y1 = math.floor(math.log10(min(values))), math.ceil(math.log10(max(values)))
    X = lambda f: left + (math.log10(f) - x0) / (x1 - x0) * (w - left - right)
    Y = lambda v: h - bottom - (math.log10(v) - y0) / (y1 - y0) * (h - bottom - top)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>']
    for e in range(x0, x1 + 1):
        out.append(f'<line x1="{X(10**e):.1f}" y1="{top}" x2="{X(10**e):.1f}" y2="{h-bottom}" stroke="#eee"/>')
        out.append(f'<text x="{X(10**e):.1f}" y="{h-bottom+18}" text-anchor="middle">10^{e}</text>')
    for e in range(y0, y1 + 1):
        out.append(f'<line x1="{left}" y1="{Y(10**e):.1f}" x2="{w-right}" y2="{Y(10**e):.1f}" stroke="#eee"/>')
        out.append(f'<text x="{left-8}" y="{Y(10**e)+4:.1f}" text-anchor="end">10^{e}</text>')
    out.append(f'<text x="{(w+left)/2}" y="{h-10}" text-anchor="middle">input faces (generated buildings)</text>')
    t = [r["wall_seconds"]["median"] for r in rows]
    anchor = 1 if len(faces) > 2 else 0  # through the 10⁴ point: the issue bounds growth from there
    reference = [t[anchor] * f * math.log(f) / (faces[anchor] * math.log(faces[anchor])) for f in faces]
    for k, (name, s, colour) in enumerate(series):
        s = s or reference
        dash = ' stroke-dasharray="5,4"' if name.startswith("n log n") else ""
        points = " ".join(f"{X(f):.1f},{Y(v):.1f}" for f, v in zip(faces, s))
        out.append(f'<polyline points="{points}" fill="none" stroke="{colour}" stroke-width="2"{dash}/>')
        for f, v in zip(faces, s):
            if not dash:
                out.append(f'<circle cx="{X(f):.1f}" cy="{Y(v):.1f}" r="3.5" fill="{colour}"/>')
        out.append(f'<text x="{left+12}" y="{top+16+16*k}" fill="{colour}">{name}</text>')
    out.append("</svg>")
    open(target, "w").write("\n".join(out) + "\n")

if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
