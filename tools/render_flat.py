#!/usr/bin/python3
"""Render a flattened vessel: the 3D surface with its cut seam (red) beside the 2D map.

  render_flat.py INPUT_MESH FLAT.obj OUT.png [--field area|none] [--overlaps REPORT.json]

FLAT.obj is vessel-flatten's output (v = input positions, vt = uv, f v/vt). The map is coloured by
log2 of the per-triangle area ratio 2D/3D (white = area kept). With --overlaps, the
triangles listed in the vessel-flatten report's "overlaps" (exact, vessel/quality/overlap.h) are red. Needs python3-numpy and
python3-matplotlib (Debian). INPUT_MESH is only used for the title.
"""
import json
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402


def read_flat_obj(path):
    V, T, F, FT = [], [], [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                V.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("vt "):
                T.append([float(x) for x in line.split()[1:3]])
            elif line.startswith("f "):
                corners = [c.split("/") for c in line.split()[1:]]
                F.append([int(c[0]) - 1 for c in corners])
                FT.append([int(c[1]) - 1 for c in corners])
    return np.array(V), np.array(T), np.array(F), np.array(FT)


def seam_edges(F, FT):
    """Edges whose two sides use different uv vertices (the cut), as pairs of 3D vertex ids."""
    sides = {}
    for f, ft in zip(F, FT):
        for k in range(3):
            a, b = f[k], f[(k + 1) % 3]
            ta, tb = ft[k], ft[(k + 1) % 3]
            key = (min(a, b), max(a, b))
            sides.setdefault(key, []).append((ta, tb) if a < b else (tb, ta))
    return [k for k, s in sides.items() if len(s) == 2 and s[0] != s[1]]


def main():
    if len(sys.argv) < 4:
        print(__doc__)
        return 2
    title, flat, out = sys.argv[1], sys.argv[2], sys.argv[3]
    overlapping = []
    if "--overlaps" in sys.argv:
        with open(sys.argv[sys.argv.index("--overlaps") + 1]) as fh:
            overlapping = json.load(fh)["overlaps"]["triangles"]
    V, T, F, FT = read_flat_obj(flat)
    a3 = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    e1, e2 = T[FT[:, 1]] - T[FT[:, 0]], T[FT[:, 2]] - T[FT[:, 0]]
    a2 = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    ratio = np.log2(np.clip(a2, 1e-300, None) / np.clip(a3, 1e-300, None))
    seam = np.array(seam_edges(F, FT)).reshape(-1, 2)

    fig = plt.figure(figsize=(14, 7))
    ax3 = fig.add_subplot(1, 2, 1, projection="3d", computed_zorder=False)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    shade = 0.35 + 0.65 * np.abs(n @ light)
    poly = Poly3DCollection(V[F], facecolors=np.c_[0.9 * shade, 0.8 * shade, 0.75 * shade, np.ones_like(shade)],
                            linewidths=0)
    ax3.add_collection3d(poly)
    if len(seam):
        # Drawn after (on top of) the surface so the whole cut stays visible.
        ax3.add_collection3d(Line3DCollection(V[seam], colors="red", linewidths=2.5, zorder=10))
    lo, hi = V.min(0), V.max(0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax3.set_xlim(c[0] - r, c[0] + r); ax3.set_ylim(c[1] - r, c[1] + r); ax3.set_zlim(c[2] - r, c[2] + r)
    ax3.set_title("3D surface, cut in red")
    ax3.set_axis_off()

    ax2 = fig.add_subplot(1, 2, 2)
    pc = PolyCollection(T[FT], array=ratio, cmap="RdBu_r", edgecolors="none")
    pc.set_clim(-1, 1)
    ax2.add_collection(pc)
    flipped = a2 <= 0
    if flipped.any():
        ax2.add_collection(PolyCollection(T[FT[flipped]], facecolors="black", edgecolors="black"))
    if overlapping:
        # Edges too, so a few small triangles stay visible on a large map.
        ax2.add_collection(PolyCollection(T[FT[overlapping]], facecolors="red", edgecolors="red",
                                          linewidths=0.6))
    ax2.autoscale(); ax2.set_aspect("equal")
    fig.colorbar(pc, ax=ax2, shrink=0.7, label="log2 area ratio 2D/3D")
    ax2.set_title(f"flattened map: {len(F)} triangles, {int(flipped.sum())} flipped, "
                  f"area ratio {a2.sum() / a3.sum():.3f}"
                  + (f", {len(overlapping)} overlapping (red)" if "--overlaps" in sys.argv else ""))
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
