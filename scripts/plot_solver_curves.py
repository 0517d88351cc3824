#!/usr/bin/env python3
"""Plot the ARAP solver study of `vessel-bench-table --solver-curves CSV`: per mesh, the energy
above the best energy either solver reached, relative to it, against seconds (log-log), with the
1e-4 line that counts as converged.

usage: scripts/plot_solver_curves.py CSV PNG
"""
import csv
import math
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TOLERANCE = 1e-4
FLOOR = 1e-9  # excess plotted at this level once a solver reaches the best energy
STYLE = {"Ceres": ("tab:red", "-"), "local/global": ("tab:blue", "-")}


def read(path):
    curves = defaultdict(lambda: defaultdict(lambda: ([], [])))
    faces = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            t, e = curves[row["mesh"]][row["solver"]]
            t.append(float(row["seconds"]))
            e.append(float(row["energy"]))
            faces[row["mesh"]] = int(row["faces"])
    return curves, faces


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    curves, faces = read(sys.argv[1])
    meshes = sorted(curves, key=lambda m: faces[m])
    cols = 3
    rows = math.ceil(len(meshes) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.3 * rows), squeeze=False)
    for ax, mesh in zip(axes.flat, meshes):
        best = min(min(e) for _, e in curves[mesh].values())
        for solver, (t, e) in sorted(curves[mesh].items()):
            colour, line = STYLE.get(solver, ("black", "-"))
            # skip the start (t = 0) on the log axis; it is the same point for both solvers
            xs = [x for x in t[1:]]
            ys = [max((y - best) / best, FLOOR) for y in e[1:]]
            ax.plot(xs, ys, line, color=colour, lw=1.3, label=solver)
            hit = next((i for i, y in enumerate(e) if y <= best * (1 + TOLERANCE)), None)
            if hit is not None and hit > 0:
                ax.plot([t[hit]], [max((e[hit] - best) / best, FLOOR)], "o", color=colour, ms=5)
        ax.axhline(TOLERANCE, color="grey", lw=0.8, ls="--")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{mesh} ({faces[mesh]} triangles)", fontsize=9)
        ax.set_xlabel("seconds since the call", fontsize=8)
        ax.set_ylabel("(E - E_best) / E_best", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="major", lw=0.3)
        ax.legend(fontsize=7, loc="upper right")
    for ax in list(axes.flat)[len(meshes):]:
        ax.axis("off")
    fig.suptitle("ARAP energy against time: Ceres vs local/global (dot: first within 1e-4 of "
                 "the best; dashed: 1e-4)", fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
