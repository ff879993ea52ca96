#!/usr/bin/env python3
"""Flat against smooth shading, per region, each against the path tracer.

Flat shading draws each element's own radiance B/π; Gouraud draws the vertex values (gathered at
their own points) interpolated over the triangles. Both picture one solution, so over a region (a
lambert surface: one smooth region of the file) their area-weighted means should agree, and agree
with the truth; where they do not, one is wrong there (issue 41: dark smudges on clustered
spheres). The mean of a linear interpolation over a triangle is the mean of its corners, so the
smooth mean is exact, not sampled. The truth is the path tracer (build/bin/vertex_reference) at
every element's centroid, an area-weighted midpoint rule over the region.

Regions compared: those that emit nothing and have no element covered by other geometry (a
partly covered element shows its open part's radiance, B / f, where the tracer at its centroid
may meet the cover; the inside of a closed two-sided object is covered), hold at least
--min-share of that area, and whose path-traced mean is above a thousandth of the brightest
such region's. Prints one
JSON document: for flat against the tracer, smooth against the tracer and smooth against flat,
the RMS and largest relative difference over the regions, how many differ by more than 5%, and
the regions where smooth and flat differ most.

    bench/flat_smooth.py --scene FILE [--sides one] [--samples 1024] [--module build/python]
                         [--vertex-reference build/bin/vertex_reference]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scene", required=True)
    parser.add_argument("--sides", choices=["file", "one", "two"], default="file")
    parser.add_argument("--samples", type=int, default=1024, help="paths a centroid for the reference")
    parser.add_argument("--module", default=os.path.join(ROOT, "build", "python"))
    parser.add_argument("--vertex-reference", default=os.path.join(ROOT, "build", "bin", "vertex_reference"))
    parser.add_argument("--min-share", type=float, default=0.001, help="smallest region compared, as a share of the area")
    args = parser.parse_args()
    sys.path.insert(0, args.module)
    import numpy as np
    import lambert

    two_sided = {"file": None, "one": False, "two": True}[args.sides]
    engine = lambert.Radiosity(lambert.load_scene(args.scene, two_sided=two_sided))
    engine.solve()
    elements = engine.elements()
    area, surface = elements["area"], elements["surface"]
    flat_radiance = engine.element_values("radiosity")[:, 1] / np.pi  # green: the luminance's largest share
    positions, triangles = engine.vertex_positions(), engine.triangles()
    corners = positions[triangles]
    triangle_area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    triangle_radiance = engine.vertex_radiance()[:, 1][triangles].mean(axis=1)
    triangle_surface = engine.triangle_surfaces()

    with tempfile.TemporaryDirectory() as scratch:
        points, traced = os.path.join(scratch, "centroids.csv"), os.path.join(scratch, "traced.csv")
        with open(points, "w") as out:
            out.write("x,y,z,nx,ny,nz,r,g,b\n")
            for c, n in zip(elements["centroid"], elements["normal"]):
                out.write(",".join(repr(float(v)) for v in (*c, *n)) + ",0,0,0\n")
        command = [args.vertex_reference, "--scene", args.scene, "--vertices", points, "--samples", str(args.samples), "-o", traced]
        if args.sides != "file":
            command += ["--sides", args.sides]
        subprocess.run(command, check=True, capture_output=True)
        reference = np.genfromtxt(traced, delimiter=",", names=True)["g"]

    regions = int(max(surface.max(initial=0), triangle_surface.max(initial=0))) + 1
    region_area = np.bincount(surface, weights=area, minlength=regions)
    mean = lambda weights, where, w, n: np.bincount(where, weights=weights * w, minlength=n) / np.maximum(np.bincount(where, weights=w, minlength=n), 1e-300)
    flat = mean(flat_radiance, surface, area, regions)
    traced_mean = mean(reference, surface, area, regions)
    smooth = mean(triangle_radiance, triangle_surface, triangle_area, regions)
    emitting = np.bincount(surface, weights=engine.element_values("emitted").max(axis=1) * area, minlength=regions) > 0
    # Only regions open all over: a partly covered element shows its open part's radiance (B / f)
    # where the tracer at its centroid may meet the cover.
    covered = np.bincount(surface, weights=(elements["open_fraction"] < 1).astype(float), minlength=regions) > 0
    quiet = ~emitting & ~covered
    compared = quiet & (region_area >= args.min_share * region_area[quiet].sum()) & \
        (traced_mean > 1e-3 * np.where(quiet, traced_mean, 0).max(initial=0))

    def summary(a, b):
        d = a[compared] / b[compared] - 1
        if d.size == 0:
            return None
        return {"rms": round(float(np.sqrt(np.mean(d ** 2))), 4), "largest": round(float(d[np.argmax(np.abs(d))]), 4),
                "over_5_percent": int((np.abs(d) > 0.05).sum())}

    apart = np.where(compared, np.abs(smooth / np.where(flat > 0, flat, 1) - 1), -1)
    worst = [int(i) for i in np.argsort(-apart)[:3] if apart[i] >= 0]
    print(json.dumps({
        "regions_compared": int(compared.sum()),
        "flat_against_traced": summary(flat, traced_mean),
        "smooth_against_traced": summary(smooth, traced_mean),
        "smooth_against_flat": summary(smooth, flat),
        "farthest_apart": [{"region": i, "area_share": round(float(region_area[i] / region_area[quiet].sum()), 4),
                            "flat_over_traced": round(float(flat[i] / traced_mean[i]), 3),
                            "smooth_over_traced": round(float(smooth[i] / traced_mean[i]), 3)} for i in worst],
    }))


if __name__ == "__main__":
    main()
