"""One case of the cohort workflow: vessel-flatten with the report, image and viewer page, and
status.json last (written atomically, so that its presence means the case is done).

map.png shows the field series' first step (vessel-flatten --image) when the case has one, else
the map coloured by its area distortion, log(2D area / 3D area) per triangle (matplotlib).

A case the library refuses (exit code 1) is not a failed job: its status is "invalid" with the
library's one-line message, and the cohort goes on. Any other failure (a crash) fails the job,
so that Snakemake reports it and reruns it next time.
"""

import json
import os
import pathlib
import subprocess
import time

import numpy as np


def draw_area_distortion(case_dir):
    """map.png: the map's triangles coloured by log(2D area / 3D area), total areas equalised."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import vessel
    cut = vessel.read(case_dir / "map.vtp")
    flat = vessel.read(case_dir / "map-map.vtp")

    def areas(p, f):
        return 0.5 * np.linalg.norm(np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]]), axis=1)

    a3, a2 = areas(cut.points, cut.faces), areas(flat.points, flat.faces)
    log_ratio = np.log((a2 / a2.sum()) / (a3 / a3.sum()))
    limit = max(0.05, float(np.percentile(np.abs(log_ratio), 99)))
    fig, ax = plt.subplots(figsize=(5, 5))
    shown = ax.tripcolor(flat.points[:, 0], flat.points[:, 1], flat.faces, facecolors=log_ratio,
                         cmap="RdBu_r", vmin=-limit, vmax=limit)
    fig.colorbar(shown, ax=ax, shrink=0.7, label="log(2D area / 3D area)")
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(case_dir.name)
    fig.savefig(case_dir / "map.png", dpi=110, bbox_inches="tight")
    plt.close(fig)


sm = snakemake  # noqa: F821 (set by Snakemake's script directive)
status_path = pathlib.Path(sm.output.status)
case_dir = status_path.parent
case_dir.mkdir(parents=True, exist_ok=True)
surface = pathlib.Path(sm.input.surface)
fields = str(sm.params.fields)

command = [sm.params.flatten, str(surface), "-o", str(case_dir / "map.vtp"),
           "--report", str(case_dir / "report.json"),
           "--html", str(case_dir / "viewer.html"), "--quiet"]
if fields:
    command += ["--fields", str(fields), "--image", str(case_dir / "map.png")]
    if fields.endswith(".pvd"):  # the middle step of the series
        steps = pathlib.Path(fields).read_text().count("<DataSet")
        command += ["--image-step", str(steps // 2)]
if sm.params.field:
    command += ["--field", sm.params.field]
command += sm.params.extra.split()

# glibc's malloc with transparent huge pages, as vessel-flatten --batch gives its mesh processes
# (fewer page faults; docs/benchmarks.md, "Machine and conditions"); a setting of the user's stays.
env = dict(os.environ)
tunables = env.get("GLIBC_TUNABLES", "")
if "glibc.malloc.hugetlb" not in tunables:
    env["GLIBC_TUNABLES"] = (tunables + ":" if tunables else "") + "glibc.malloc.hugetlb=1"
start = time.monotonic()
done = subprocess.run(command, capture_output=True, text=True, env=env)
wall = time.monotonic() - start
status = {"case": case_dir.name, "surface": str(surface), "fields": str(fields) if fields else None,
          "wall_s": wall, "command": command}
if done.returncode == 0:
    status["status"] = "ok"
    status["message"] = ""
    if not fields:
        draw_area_distortion(case_dir)
elif done.returncode == 1:
    message = done.stderr.strip().splitlines()[-1] if done.stderr.strip() else ""
    status["status"] = "invalid"
    status["message"] = message.removeprefix("vessel-flatten: ")
else:
    raise RuntimeError(f"vessel-flatten ended with code {done.returncode} on {surface}:\n"
                       f"{done.stderr}")
tmp = status_path.with_suffix(".json.tmp")
tmp.write_text(json.dumps(status, indent=2) + "\n")
os.replace(tmp, status_path)
