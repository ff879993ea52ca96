"""Convergence of a radiosity solve, sweep by sweep, plotted with matplotlib.

    PYTHONPATH=build/python python3 examples/python/convergence.py [--scene cornell] [-o out/convergence.png]

Solves the scene one Gauss-Seidel sweep at a time (solve(max_sweeps=1)) with the flat method and
with the default hierarchical one, reads the solver's relative residual after each sweep from
stats(), and plots both on a log scale. Prints one line per sweep: method, sweep, residual.
"""
import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import lambert


def residuals(scene, sweeps, **options):
    engine = lambert.Radiosity(scene, **options)
    out = []
    for _ in range(sweeps):
        report = engine.solve(max_sweeps=1)
        out.append(engine.stats()["residual"])
        if report["converged"]:
            break
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="cornell")
    parser.add_argument("--sweeps", type=int, default=30)
    parser.add_argument("-o", "--output", default="out/convergence.png")
    args = parser.parse_args()
    scene = lambert.load_scene(args.scene)
    runs = {
        "flat, 2000 patches": residuals(scene, args.sweeps, method="flat", patches=2000, tolerance=1e-9),
        "hierarchical (default)": residuals(scene, args.sweeps, tolerance=1e-9),
    }
    for name, values in runs.items():
        for sweep, value in enumerate(values, 1):
            print(f"{name}\t{sweep}\t{value:.3e}")
    figure, axes = plt.subplots(figsize=(6, 4))
    for name, values in runs.items():
        axes.semilogy(range(1, len(values) + 1), values, marker="o", markersize=3, label=name)
    axes.set_xlabel("Gauss-Seidel sweep")
    axes.set_ylabel("relative residual")
    axes.set_title(f"lambert: {scene.name}")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.tight_layout()
    import os
    os.makedirs(os.path.dirname(args.output) or ".", exist_ok=True)
    figure.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
