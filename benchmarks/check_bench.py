#!/usr/bin/env python3
"""Smoke checks of the benchmark executables on a real mesh (ctest; no timing is judged).

  check_bench.py table EXE MESH WORKDIR   vessel-bench-table, each --method, 2 runs, with the peer
  check_bench.py cut EXE MESH_NAME        vessel-cut-bench's VC/check/ and VC/bare/ on one mesh

Each check reads the executable's JSON and asserts properties of what it measured: every stage
timed in every run, the runs' totals equal to the sums of their stages, a peak RSS, both
pipelines' map quality and cut winding reported, and the peer's search on our costs finding our
paths; and `targets_table.py`, read on the default's and the paper's method's runs, prints the
mesh's row with their median Totals and the peer's. The quality bounds are requirements per
method, each of which a broken value fails:

- every map of ours (and the peer's ARAP map): total area ratio within AREA_RATIO_TOLERANCE of 1
  (stage F maps at the surface's scale; the same bound as pipeline_test's real meshes);
- the default method: no flipped and no overlapping triangle (issue 7); paper-untangled: no
  flipped triangle; paper: flips and overlaps are the paper's (their figures are guarded on real
  meshes by tests/pipeline/paper_guard_test.cpp), here only counted consistently;
- every cut of ours winds at most MAX_CUT_WINDING_DEG around its vessel, the seam at most
  MAX_MEAN_WINDING_DEG on average (issue 32's bounds on a natural cut), on a measured part of the
  cut; the peer's cuts less than half a turn (a cut that turns further is no longitudinal cut).

Exits non-zero with a message on the first failure.
"""
import json
import math
import os
import subprocess
import sys

STAGES = ["Z", "GC", "VC", "AC", "L", "F"]
PEER_STAGES = ["Z", "GC", "VC", "AC", "F"]
# A map's total area over the surface's: stage F maps at the surface's scale (ARAP and SLIM are
# isometry-seeking), so a map that lost or gained more than this is a broken stage F.
AREA_RATIO_TOLERANCE = 0.05
# Issue 32: every cut winds at most this many degrees around its vessel (the bound of
# CutPlanOptions::winding_limit_deg), the seam's length-weighted mean at most the
# second; the meter's figure rests on the cut vertices that lie on a clean ring.
MAX_CUT_WINDING_DEG = 45.0
MAX_MEAN_WINDING_DEG = 20.0
# The peer's cuts (its own cost and cut rule): less than half a turn around the vessel.
MAX_PEER_WINDING_DEG = 180.0


def fail(message):
    sys.exit("check_bench: " + message)


def expect(condition, message):
    if not condition:
        fail(message)


def check_samples(where, stages, names, runs):
    for name in names + ["Total"]:
        expect(name in stages, f"{where}: stage {name} missing")
        samples = stages[name]["samples"]
        expect(len(samples) == runs, f"{where}: {name} has {len(samples)} samples, not {runs}")
        expect(all(s >= 0.0 and math.isfinite(s) for s in samples),
               f"{where}: {name} has a negative or non-finite time {samples}")
        expect(stages[name]["min"] <= stages[name]["median"] <= stages[name]["max"],
               f"{where}: {name} median outside min-max")
    for k in range(runs):
        total = stages["Total"]["samples"][k]
        parts = sum(stages[n]["samples"][k] for n in names)
        expect(abs(total - parts) <= 1e-9 + 1e-9 * total,
               f"{where}: run {k + 1} Total {total} is not the sum of its stages {parts}")
    expect(stages["Total"]["median"] > 0.0, f"{where}: zero total time")


def check_cpu(where, cpu, wall):
    """Each run's CPU seconds: as many as its wall times, none negative, some in user space, and
    no more than the machine's cores could give in its wall time (getrusage's granularity,
    a few milliseconds, aside)."""
    cores = os.cpu_count() or 1
    for kind in ("user", "kernel"):
        samples = cpu[kind]["samples"]
        expect(len(samples) == len(wall), f"{where}: {len(samples)} {kind} CPU samples for "
               f"{len(wall)} runs")
        expect(all(s >= 0.0 and math.isfinite(s) for s in samples),
               f"{where}: negative or non-finite {kind} CPU seconds {samples}")
    expect(cpu["user"]["median"] > 0.0, f"{where}: no CPU time in user space")
    for k, seconds in enumerate(wall):
        used = cpu["user"]["samples"][k] + cpu["kernel"]["samples"][k]
        expect(used <= cores * seconds + 0.05,
               f"{where}: run {k + 1} used {used} CPU s in {seconds} s on {cores} cores")


def check_winding(where, quality, max_deg, max_mean_deg):
    expect("seam_winding" in quality, f"{where}: no seam_winding")
    w = quality["seam_winding"]
    expect(0.0 <= w["mean_abs_deg"] <= w["max_abs_deg"] <= max_deg,
           f"{where}: seam winding {w}: a cut winds more than {max_deg} degrees")
    expect(w["mean_abs_deg"] <= max_mean_deg,
           f"{where}: seam winding {w}: mean above {max_mean_deg} degrees")
    expect(0.0 < w["measured_fraction"] <= 1.0,
           f"{where}: measured fraction {w} (no cut vertex on a clean ring: no figure)")


def check_area_ratio(where, quality):
    ratio = quality["area_ratio"]
    expect(abs(ratio - 1.0) <= AREA_RATIO_TOLERANCE,
           f"{where}: area ratio {ratio}, not within {AREA_RATIO_TOLERANCE} of 1")


def host_discards_freed_pages():
    """Whether a virtio memory balloon (device 0x0005) negotiates free page reporting
    (VIRTIO_BALLOON_F_REPORTING, feature bit 5), read from sysfs as the tools read it."""
    root = "/sys/bus/virtio/devices"
    try:
        devices = os.listdir(root)
    except OSError:
        return False
    for name in devices:
        try:
            with open(os.path.join(root, name, "device")) as f:
                device = f.readline().strip()
            with open(os.path.join(root, name, "features")) as f:
                features = f.readline().strip()
        except OSError:
            continue
        if device.startswith("0x0005") and len(features) > 5 and features[5] == "1":
            return True
    return False


def expected_huge_pages():
    """Whether vessel-bench-table's process has glibc's malloc on transparent huge pages: the
    environment's own setting where it names one, else whether the kernel gives them and the
    host keeps the memory the guest frees (the bench then starts itself again with them)."""
    tunables = os.environ.get("GLIBC_TUNABLES", "")
    if "glibc.malloc.hugetlb=" in tunables:
        value = tunables.split("glibc.malloc.hugetlb=", 1)[1][:1]
        return value in ("1", "2")
    try:
        with open("/sys/kernel/mm/transparent_hugepage/enabled") as f:
            gives = "[never]" not in f.readline()
    except OSError:
        return False
    return gives and not host_discards_freed_pages()


def cpu_has_avx2_fma():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    flags = line.split(":", 1)[1].split()
                    return "avx2" in flags and "fma" in flags
    except OSError:
        pass
    return False


def check_blas_kernels(where, kernels):
    """The kernels OpenBLAS ran in the bench's process: the Haswell kernels' rounding (Haswell's
    own or the Zen target's) where the CPU has AVX2 and FMA and the environment names none
    (tools/common/blas_kernels.h); "" where the BLAS is not OpenBLAS."""
    if kernels and cpu_has_avx2_fma() and "OPENBLAS_CORETYPE" not in os.environ:
        expect(kernels in ("Haswell", "Zen"),
               f"{where}: OpenBLAS ran its {kernels} kernels, not the Haswell kernels the "
               f"bench's start-up (restart_for_run) should have asked for")


def check_table(exe, mesh, workdir):
    os.makedirs(workdir, exist_ok=True)
    # The paper's whole method (its F and its cut rule) is the like-for-like run beside the peer.
    for method, cuts in [("default", "default"), ("paper", "default"),
                         ("paper-untangled", "default"), ("paper-untangled", "paper")]:
        out = os.path.join(workdir, f"table-{method}-{cuts}.json")
        subprocess.run([exe, "--runs", "2", "--method", method, "--cuts", cuts,
                        "--peer-timeout", "120", "--json", out, mesh],
                       check=True, stdout=subprocess.DEVNULL)
        with open(out) as f:
            doc = json.load(f)
        expect(doc["runs"] == 2, f"{method}: runs {doc['runs']}")
        expect(doc["huge_pages"] == expected_huge_pages(),
               f"{method}: huge_pages {doc['huge_pages']}, not what the bench's start-up "
               f"(restart_for_run) should have set")
        check_blas_kernels(method, doc["blas_kernels"])
        expect(len(doc["results"]) == 1, f"{method}: {len(doc['results'])} results for one mesh")
        r = doc["results"][0]
        where = f"{method} --cuts {cuts} {r['name']}"
        expect(r["method"] == method, f"{where}: ran method {r['method']}")
        expect(r["cuts"] == cuts, f"{where}: ran cut rule {r['cuts']}")
        expect("error" not in r, f"{where}: {r.get('error')}")
        check_samples(where, r["stages"], STAGES, 2)
        expect(r["peak_rss_mb"] > 0.0, f"{where}: no peak RSS")
        check_cpu(where, r["cpu"], r["wall"]["samples"])
        expect(r["faces"] > 0 and r["cut_paths"] >= 1, f"{where}: faces/cuts {r['faces']}, "
               f"{r['cut_paths']}")
        q = r["quality"]
        check_winding(where, q, MAX_CUT_WINDING_DEG, MAX_MEAN_WINDING_DEG)
        check_area_ratio(where, q)
        if method == "default":  # the library's default map is one-to-one (issue 7)
            expect(q["flipped_triangles"] == 0 and q["overlapping_triangles"] == 0
                   and q["overlap_fraction"] == 0.0,
                   f"{where}: {q['flipped_triangles']} flipped, "
                   f"{q['overlapping_triangles']} overlapping triangles")
        elif method == "paper-untangled":  # the paper's F, then no flipped triangle
            expect(q["flipped_triangles"] == 0,
                   f"{where}: {q['flipped_triangles']} flipped triangles")
        # Overlaps, where a method allows them, are counted consistently: triangles and area.
        expect(0 <= q["flipped_triangles"] <= r["faces"]
               and 0 <= q["overlapping_triangles"] <= r["faces"]
               and (q["overlapping_triangles"] > 0) == (q["overlap_fraction"] > 0.0)
               and 0.0 <= q["overlap_fraction"] < 1.0,
               f"{where}: overlap counts {q['overlapping_triangles']} triangles, fraction "
               f"{q['overlap_fraction']}, flips {q['flipped_triangles']} of {r['faces']} faces")
        p = r["peer"]
        where = f"{method} --cuts {cuts} {r['name']} (peer)"
        expect(not p.get("errors"), f"{where}: {p.get('errors')}")
        check_samples(where, p["stages"], PEER_STAGES, p["runs"])
        expect(p["peak_rss_mb"] > 0.0, f"{where}: no peak RSS")
        expect(p["cut_paths"] == r["cut_paths"],
               f"{where}: {p['cut_paths']} cuts against ours {r['cut_paths']}")
        check_winding(where, p["quality"], MAX_PEER_WINDING_DEG, MAX_PEER_WINDING_DEG)
        expect("arap" in p["quality"], f"{where}: no ARAP quality")
        check_area_ratio(where + " ARAP", p["quality"]["arap"])
    check_targets_table(os.path.join(workdir, "table-default-default.json"),
                        os.path.join(workdir, "table-paper-default.json"))
    print(f"check_bench table: {mesh}: all four pipelines, ours and the peer, checked")


def check_targets_table(default_json, paper_json):
    """targets_table.py on the runs above: the mesh's row reads the medians of both methods'
    Totals and the peer's, in the real trees' table."""
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, here)
    from targets_table import seconds  # the script's own rounding of a median
    script = os.path.join(here, "targets_table.py")
    run = subprocess.run([sys.executable, script, "--default", default_json,
                          "--paper", paper_json], check=True, capture_output=True, text=True)
    with open(default_json) as f:
        ours = json.load(f)["results"][0]
    with open(paper_json) as f:
        paper = json.load(f)["results"][0]
    tables = run.stdout.split("**Carotid phantoms**")
    expect(len(tables) == 2 and "**Real trees**" in tables[0],
           f"targets_table: no real trees' and phantoms' tables in\n{run.stdout}")
    rows = [line for line in tables[0].splitlines() if line.startswith("| ") and "---" not in line]
    expect(len(rows) == 2, f"targets_table: {len(rows) - 1} rows for one real mesh")
    cells = [c.strip() for c in rows[1].strip("|").split("|")]
    header = [c.strip() for c in rows[0].strip("|").split("|")]
    row = dict(zip(header, cells))

    expect(row["Total"] == seconds(ours["stages"]["Total"]["median"]),
           f"targets_table: Total {row['Total']}, the runs' median "
           f"{ours['stages']['Total']['median']}")
    theirs = row["paper's method"]
    expect(theirs == seconds(paper["stages"]["Total"]["median"]),
           f"targets_table: paper's method {theirs}, the runs' median "
           f"{paper['stages']['Total']['median']}")
    expect(row["CGAL peer"] == seconds(ours["peer"]["stages"]["Total"]["median"]),
           f"targets_table: CGAL peer {row['CGAL peer']}, its runs' median "
           f"{ours['peer']['stages']['Total']['median']}")


def check_cut(exe, mesh_name):
    escaped = mesh_name.replace(".", "\\.")
    run = subprocess.run([exe, f"--benchmark_filter=VC/(check|bare|peer-our-costs)/{escaped}",
                          "--benchmark_min_time=0.01", "--benchmark_format=json"],
                         check=True, capture_output=True, text=True)
    rows = {b["name"].split("/")[1]: b for b in json.loads(run.stdout)["benchmarks"]}
    for kind in ["check", "bare", "peer-our-costs"]:
        expect(kind in rows, f"VC/{kind}/{mesh_name} did not run")
    check = rows["check"]
    expect(check["outlets"] >= 1 and check["equal_paths"] == check["outlets"],
           f"the peer's search on our costs found {check['equal_paths']} of "
           f"{check['outlets']} paths equal to plan_cuts' bare rule")
    expect(rows["bare"]["seam_edges"] == rows["peer-our-costs"]["seam_edges"],
           f"VC/bare/ cut {rows['bare']['seam_edges']} seam edges, the peer on our costs "
           f"{rows['peer-our-costs']['seam_edges']}")
    print(f"check_bench cut: {mesh_name}: {check['equal_paths']}/{check['outlets']} equal paths")


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "table":
        check_table(*sys.argv[2:])
    elif len(sys.argv) == 4 and sys.argv[1] == "cut":
        check_cut(*sys.argv[2:])
    else:
        sys.exit(__doc__)
