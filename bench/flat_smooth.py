#!/usr/bin/env python3
"""Flat against smooth shading, per region: what --shading flat and Gouraud show of one solve.

Flat shading draws each element's own radiance B/π; Gouraud draws the vertex values (gathered at
their own points) interpolated over the triangles. Both are pictures of one solution, so over a
region (a lambert surface: one smooth region of the file) their area-weighted means should agree;
where they do not, one of them is wrong there (issue 41: dark smudges on clustered spheres, a
bright band where two touch). The mean of a linear interpolation over a triangle is the mean of
its corners, so the smooth mean is exact, not sampled.

For each region of at least --min-share of the scene's lit area (regions whose flat mean is
above a thousandth of the brightest region's), it reports the relative difference of the smooth
mean from the flat one; prints one JSON document: the regions compared, how many differ by more
than 5%, the largest difference and its region, the RMS of the differences.

    bench/flat_smooth.py --scene FILE [--sides one] [--module build/python]
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scene", required=True)
    parser.add_argument("--sides", choices=["file", "one", "two"], default="file")
    parser.add_argument("--module", default=os.path.join(ROOT, "build", "python"))
    parser.add_argument("--min-share", type=float, default=0.001, help="smallest region compared, as a share of the lit area")
    args = parser.parse_args()
    sys.path.insert(0, args.module)
    import numpy as np
    import lambert

    two_sided = {"file": None, "one": False, "two": True}[args.sides]
    engine = lambert.Radiosity(lambert.load_scene(args.scene, two_sided=two_sided))
    engine.solve()
    elements = engine.elements()
    radiance = engine.element_values("radiosity").mean(axis=1) / np.pi
    area = elements["area"]
    surface = elements["surface"]
    positions = engine.vertex_positions()
    triangles = engine.triangles()
    corners = positions[triangles]
    triangle_area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    triangle_radiance = engine.vertex_radiance().mean(axis=1)[triangles].mean(axis=1)
    triangle_surface = engine.triangle_surfaces()
    regions = int(max(surface.max(initial=0), triangle_surface.max(initial=0))) + 1
    flat_power = np.bincount(surface, weights=radiance * area, minlength=regions)
    flat_area = np.bincount(surface, weights=area, minlength=regions)
    smooth_power = np.bincount(triangle_surface, weights=triangle_radiance * triangle_area, minlength=regions)
    smooth_area = np.bincount(triangle_surface, weights=triangle_area, minlength=regions)
    flat = np.divide(flat_power, flat_area, out=np.zeros(regions), where=flat_area > 0)
    smooth = np.divide(smooth_power, smooth_area, out=np.zeros(regions), where=smooth_area > 0)
    lit = flat > 1e-3 * flat.max(initial=0)
    compared = lit & (flat_area >= args.min_share * flat_area[lit].sum())
    difference = np.where(compared, smooth / np.where(flat > 0, flat, 1) - 1, 0)
    worst = int(np.argmax(np.abs(difference))) if compared.any() else -1
    print(json.dumps({
        "regions_compared": int(compared.sum()),
        "regions_over_5_percent": int((np.abs(difference[compared]) > 0.05).sum()),
        "largest_difference": round(float(difference[worst]), 4) if worst >= 0 else None,
        "largest_difference_region": worst,
        "largest_difference_region_area_share": round(float(flat_area[worst] / flat_area[lit].sum()), 4) if worst >= 0 else None,
        "rms_difference": round(float(np.sqrt(np.mean(difference[compared] ** 2))), 4) if compared.any() else None,
    }))


if __name__ == "__main__":
    main()
