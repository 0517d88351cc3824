#!/usr/bin/env python3
"""The default pipeline beside the paper's method, the paper's Table 1 and the CGAL peer.

Reads the JSON files that `vessel-bench-table --json FILE` writes and prints two Markdown tables,
one per mesh set (the real trees, the carotid phantoms): per mesh the default's median Total and
its stages Z, VC and F (s), issue 27's target, the paper's method's median Total (the runs made
with `--method paper`), the paper's own Table 1 (Eulzer et al., Python + libigl on an 8-core
Ryzen 7 5800X; carotid 44k and 300k only), the CGAL peer's Total (or where its ARAP fails), and
the maps' quality, the peak RSS, and the CPU seconds a run spent in the kernel (mostly page
faults, which a guest whose host discards the pages it frees pays at every fresh page;
docs/benchmarks.md, "Machine and conditions"). The paper's Table 1 is read from the files too
(`paper_table_1`, written by the bench beside its results). Medians are over every sample of
every file given for a method, so several runs of the bench can be pooled.

    /usr/bin/python3 benchmarks/targets_table.py --default default.json [more.json ...] \
        --paper paper.json [more.json ...]

The peer's column is read from the default files that ran it (without `--no-peer`).
"""

import argparse
import json
import re
import statistics

# Issue 27's targets for the default (Total, s).
TARGETS = {
    "pulmonary-glenn-wall": 1.5,
    "pulmonary-glenn-wall-split4": 6.0,
    "carotid-44k": 0.5,
    "carotid-300k": 3.0,
    "carotid-1M": 15.0,
}
LABELS = {
    "aorta-surface-open-ends": "vmtk aorta",
    "artery": "VaMPy artery",
    "artery-coarse": "VaMPy artery-coarse",
    "aneurisk-id1-lateral-aneurysm": "AneuRisk id1",
    "pulmonary-glenn-wall": "pulmonary Glenn",
    "pulmonary-glenn-wall-split4": "Glenn split4",
    "coronary-phantom-tri3-coarse": "coronary phantom",
    "coronary-clinical-branch-fine": "coronary clinical branch",
    "demo-model-open": "SimVascular demo",
}


def load(paths):
    """Each mesh's result rows (one per file that ran it), in the first file's order, and the
    paper's Table 1 as the files give it."""
    rows, table_1 = {}, {}
    for path in paths:
        with open(path) as f:
            doc = json.load(f)
        table_1.update(doc.get("paper_table_1", {}))
        for row in doc["results"]:
            if "stages" in row:
                rows.setdefault(row["name"], []).append(row)
    return rows, table_1


def samples(rows, stage):
    return [x for row in rows for x in row["stages"][stage]["samples"]]


def median(rows, stage):
    return statistics.median(samples(rows, stage))


def seconds(x):
    return "%.2f" % x if x >= 1 else "%.3f" % x if x >= 0.1 else "%.3g" % x


def peer_total(rows):
    """The peer's median Total, where it failed, or why it was not run ('–' if never asked)."""
    for row in rows:
        peer = row.get("peer")
        if not peer:
            continue
        if peer.get("skipped"):
            return "not run"
        if peer.get("error"):
            return "failed"
        for stage, message in (peer.get("errors") or {}).items():
            after = re.search(r"after ([0-9.]+) s", message)
            return "fails in %s%s" % (stage, " after %.1f s" % float(after.group(1)) if after else "")
        return seconds(peer["stages"]["Total"]["median"])
    return "–"


def peer_area(rows):
    for row in rows:
        arap = ((row.get("peer") or {}).get("quality") or {}).get("arap") or {}
        if "mean_abs_log_area_ratio" in arap:
            return "%.4f" % arap["mean_abs_log_area_ratio"]
    return "–"


def kernel_seconds(rows):
    """The median CPU seconds a run spent in the kernel, its threads' together ('–' where the
    bench did not record them)."""
    kernel = [x for row in rows
              for x in (row.get("cpu") or {}).get("kernel", {}).get("samples", [])]
    return seconds(statistics.median(kernel)) if kernel else "–"


def table(names, default, paper, table_1):
    out = [
        "| mesh | triangles | Total | Z | VC | F | target | paper's method | paper's Table 1 | "
        "CGAL peer | mean \\|log A\\| (default / paper's method / peer) | flipped / overlapping "
        "(default; paper's method) | largest cut winding, deg | peak RSS MB | "
        "CPU s in the kernel |",
        "|:--|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|",
    ]
    for name in names:
        rows, theirs = default[name], paper.get(name)
        q = rows[0]["quality"]
        pq = theirs[0]["quality"] if theirs else None
        cells = [
            LABELS.get(name, name),
            "{:,}".format(rows[0]["faces"]).replace(",", " "),
            seconds(median(rows, "Total")),
            seconds(median(rows, "Z")),
            seconds(median(rows, "VC")),
            seconds(median(rows, "F")),
            "%g" % TARGETS[name] if name in TARGETS else "",
            seconds(median(theirs, "Total")) if theirs else "–",
            "%g" % table_1[name]["Total"] if name in table_1 else "",
            peer_total(rows),
            "%.4f / %s / %s"
            % (
                q["mean_abs_log_area_normalized"],
                "%.4f" % pq["mean_abs_log_area_normalized"] if pq else "–",
                peer_area(rows),
            ),
            "%d / %d; %s"
            % (
                q["flipped_triangles"],
                q["overlapping_triangles"],
                "%d / %d" % (pq["flipped_triangles"], pq["overlapping_triangles"]) if pq else "–",
            ),
            "%.0f" % q["seam_winding"]["max_abs_deg"],
            "%.0f" % max(row["peak_rss_mb"] for row in rows),
            kernel_seconds(rows),
        ]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--default", nargs="+", required=True, help="vessel-bench-table JSON files")
    parser.add_argument("--paper", nargs="+", default=[], help="the same with --method paper")
    args = parser.parse_args()
    (default, table_1), (paper, _) = load(args.default), load(args.paper)
    real = [n for n in default if not n.startswith("carotid-")]
    phantoms = [n for n in default if n.startswith("carotid-")]
    print("**Real trees**\n\n" + table(real, default, paper, table_1))
    print("\n**Carotid phantoms**\n\n" + table(phantoms, default, paper, table_1))
    print()
    for name in default:
        total = samples(default[name], "Total")
        line = "%s: Total %s (%s-%s, %d runs)" % (
            name, seconds(statistics.median(total)), seconds(min(total)), seconds(max(total)),
            len(total))
        if name in TARGETS:
            line += ", %.2fx the target" % (statistics.median(total) / TARGETS[name])
        if name in paper:
            line += ", %.2fx the paper's method" % (
                statistics.median(total) / median(paper[name], "Total"))
        print(line)


if __name__ == "__main__":
    main()
