"""The cohort workflow (workflows/cohort, Snakemake) on a small cohort made from
../shared/data/real: valid and refused meshes mixed, interrupted and resumed."""

import csv
import json
import os
import pathlib
import re
import signal
import subprocess
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
WORKFLOW = ROOT / "workflows" / "cohort"
# Refused cases of make_test_cohort.sh and words of their documented messages.
REFUSED = {
    "aorta-closed": "the surface is closed (no open ends)",
    "aneurysm-duplicate-face": "1 duplicate face",
    "aorta-split": "coincident boundary loops",
}


def snakemake(out, cohort, flatten_exe, *more):
    return subprocess.Popen(
        ["snakemake", "-s", str(WORKFLOW / "Snakefile"), "--cores", "2", "--directory",
         str(out / "work"), "--config", f"cohort={cohort}", f"out={out / 'result'}",
         f"flatten={flatten_exe}", *more],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)


def test_cohort_interrupted_and_resumed(tmp_path, flatten_exe):
    cohort = tmp_path / "cohort"
    subprocess.run([str(WORKFLOW / "make_test_cohort.sh"), str(cohort),
                    str(pathlib.Path(flatten_exe).parent)], check=True, capture_output=True)
    cases = sorted(p.name for p in cohort.iterdir())
    assert len(cases) == 8
    result = tmp_path / "result"
    statuses = lambda: sorted(result.glob("cases/*/status.json"))

    # First run, interrupted (as Ctrl-C would) once Snakemake has seen two cases finish.
    first = snakemake(tmp_path, cohort, flatten_exe)
    lines = []

    def read_log():
        for line in first.stdout:
            lines.append(line)

    reader = threading.Thread(target=read_log, daemon=True)
    reader.start()

    def finished_cases():
        log = "".join(lines)
        outputs = dict(re.findall(r"output: (\S+/status\.json)\n\s+jobid: (\d+)", log))
        outputs = {jobid: pathlib.Path(path) for path, jobid in outputs.items()}
        return [outputs[j] for j in re.findall(r"Finished job (\d+)\.", log) if j in outputs]

    deadline = time.monotonic() + 600
    while len(finished_cases()) < 2 and first.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(first.pid, signal.SIGINT)
    first.wait(timeout=120)
    reader.join(timeout=60)
    # A job still ending at the interrupt is incomplete to Snakemake and is redone, as it should.
    finished = {p: p.stat().st_mtime_ns for p in finished_cases()}
    assert 2 <= len(finished) < len(cases), "".join(lines)
    assert not (result / "summary.csv").exists()

    # Restarted: the finished cases are kept, the rest done.
    second = snakemake(tmp_path, cohort, flatten_exe, "--rerun-incomplete")
    log, _ = second.communicate(timeout=1200)
    assert second.returncode == 0, log
    for path, mtime in finished.items():
        assert path.stat().st_mtime_ns == mtime, f"{path} was redone"
    assert len(statuses()) == len(cases)

    summary = json.loads((result / "summary.json").read_text())
    assert summary["cases"] == len(cases)
    assert summary["ok"] == len(cases) - len(REFUSED)
    invalid = {r["case"]: r["message"] for r in summary["invalid"]}
    assert set(invalid) == set(REFUSED)
    for case, start in REFUSED.items():
        assert start in invalid[case], invalid[case]
    with open(result / "summary.csv") as f:
        rows = {r["case"]: r for r in csv.DictReader(f)}
    assert set(rows) == set(cases)
    for case, row in rows.items():
        if case in REFUSED:
            assert row["status"] == "invalid" and row["message"] == invalid[case]
            continue
        assert row["status"] == "ok" and row["message"] == ""
        assert float(row["t_total"]) > 0 and int(row["flipped_triangles"]) == 0
        report = json.loads((result / "cases" / case / "report.json").read_text())
        assert float(row["mean_abs_log_area_ratio"]) == report["quality"]["mean_abs_log_area_ratio"]
        for name in ("map.vtp", "map-map.vtp", "map.png", "viewer.html"):
            assert (result / "cases" / case / name).stat().st_size > 0, (case, name)
    # The case with a field series has it over time.
    assert (result / "cases" / "artery-coarse" / "map.case").exists()
    assert (result / "overview.png").stat().st_size > 10000
