"""The cohort's summary: one row per case (status, message, timings, quality) as CSV and JSON,
and an overview image with every valid case's map (small multiples)."""

import csv
import json
import math
import pathlib

import matplotlib
matplotlib.use("Agg")
import matplotlib.image as mpimg
import matplotlib.pyplot as plt

sm = snakemake  # noqa: F821 (set by Snakemake's script directive)

TIMINGS = ["read", "Z", "GC", "VC", "AC", "L", "F", "total", "write"]
QUALITY = ["flipped_triangles", "area_ratio", "mean_abs_log_area_ratio",
           "mean_conformal_distortion", "overlapping_triangles", "seam_alignment"]

rows = []
for status_file in sorted(sm.input):
    status = json.loads(pathlib.Path(status_file).read_text())
    row = {"case": status["case"], "status": status["status"], "message": status["message"],
           "surface": status["surface"], "fields": status["fields"] or "",
           "wall_s": round(status["wall_s"], 3)}
    report_path = pathlib.Path(status_file).parent / "report.json"
    if status["status"] == "ok" and report_path.exists():
        report = json.loads(report_path.read_text())
        row["vertices"] = report["counts"]["vertices"]
        row["faces"] = report["counts"]["faces"]
        row["cuts"] = len(report["cuts"])
        row["relief_cuts"] = len(report["relief_cuts"])
        row.update({f"t_{k}": report["timings"].get(k) for k in TIMINGS})
        row.update({k: report["quality"].get(k) for k in QUALITY})
    rows.append(row)

columns = ["case", "status", "message", "surface", "fields", "wall_s", "vertices", "faces",
           "cuts", "relief_cuts"] + [f"t_{k}" for k in TIMINGS] + QUALITY
with open(sm.output.csv, "w", newline="") as f:
    writer = csv.DictWriter(f, fieldnames=columns)
    writer.writeheader()
    for row in rows:
        writer.writerow({k: row.get(k, "") for k in columns})

summary = {
    "cases": len(rows),
    "ok": sum(r["status"] == "ok" for r in rows),
    "invalid": [{"case": r["case"], "message": r["message"]} for r in rows
                if r["status"] != "ok"],
    "rows": rows,
}
pathlib.Path(sm.output.json).write_text(json.dumps(summary, indent=2) + "\n")

ok = [r for r in rows if r["status"] == "ok"]
cols = max(1, math.ceil(math.sqrt(len(ok))))
lines = max(1, math.ceil(len(ok) / cols))
fig, axes = plt.subplots(lines, cols, figsize=(3.2 * cols, 3.2 * lines), squeeze=False)
for ax in axes.flat:
    ax.axis("off")
for ax, row in zip(axes.flat, ok):
    image = pathlib.Path(sm.input[0]).parents[1] / row["case"] / "map.png"
    if image.exists():
        ax.imshow(mpimg.imread(str(image)))
    ax.set_title(f"{row['case']}\n|log area| {row['mean_abs_log_area_ratio']:.3f}", fontsize=8)
fig.suptitle(f"{len(ok)} of {len(rows)} cases flattened", fontsize=10)
fig.tight_layout()
fig.savefig(sm.output.overview, dpi=110)
