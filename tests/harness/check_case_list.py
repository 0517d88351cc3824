#!/usr/bin/env python3
"""Checks that ctest runs every doctest case once, under its own name.

doctest_discover_tests makes one ctest entry per name that `EXE --list-test-cases` prints, and the
entry runs `EXE --test-case=<name>`. Entries go wrong silently: a name holding ';' becomes two
entries (CMake's list separator) that select no case; a ',' or a '*' in a name is a filter
separator or wildcard to doctest; two cases of one name run under one entry; a case whose name
has a ',' loses its suite's label (discovery looks the suite up with the name unescaped).

This compares the doctest list with `ctest --show-only=json-v1` and asks the executable itself
(`--count` with each entry's own arguments) how many cases each entry selects. It fails, listing
every difference, unless each case has exactly one entry of its name, that entry selects exactly
that one case, every entry running EXE is such an entry, and each case carries its suite's label.

Usage: check_case_list.py --exe EXE --build-dir DIR [--ctest CTEST]
"""
import argparse
import json
import os
import re
import subprocess
import sys
from collections import Counter


def doctest_lines(command):
    """The names a doctest listing prints (one a line, without its banner lines)."""
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return [line for line in out.split("\n")
            if line and not line.startswith("[doctest]") and not re.fullmatch(r"=+", line)]


def selected_count(command):
    """How many cases `command` (an entry's own command line) selects, as doctest counts them."""
    out = subprocess.run(command + ["--count"], check=True, capture_output=True, text=True).stdout
    match = re.search(r"test cases passing the current filters: (\d+)", out)
    if not match:
        raise RuntimeError(f"no count in the output of {command + ['--count']}:\n{out}")
    return int(match.group(1))


def ctest_entries(ctest, build_dir):
    """(name, command, labels) of every ctest entry in build_dir."""
    out = subprocess.run([ctest, "--show-only=json-v1", "--test-dir", build_dir], check=True,
                         capture_output=True, text=True).stdout
    entries = []
    for test in json.loads(out)["tests"]:
        labels = []
        for prop in test.get("properties", []):
            if prop["name"] == "LABELS":
                labels = prop["value"]
        entries.append((test["name"], test.get("command", []), labels))
    return entries


def problems(exe, build_dir, ctest):
    found = []
    cases = doctest_lines([exe, "--list-test-cases"])
    suites_of = {}
    for suite in doctest_lines([exe, "--list-test-suites"]):
        for case in doctest_lines([exe, f"--test-suite={suite}", "--list-test-cases"]):
            suites_of.setdefault(case, set()).add(suite)

    for name, n in sorted(Counter(cases).items()):
        if n > 1:
            found.append(f"{n} doctest cases are named '{name}': give each a name of its own")

    exe_path = os.path.realpath(exe)
    runs_exe = [(name, command, labels) for name, command, labels in ctest_entries(ctest, build_dir)
                if command and os.path.realpath(command[0]) == exe_path]
    entries_of = Counter(name for name, _, _ in runs_exe)
    for name in sorted(set(cases)):
        if entries_of[name] != 1:
            hint = (" (a ';' in a name is CMake's list separator: discovery splits it into two "
                    "entries; reword the name)" if ";" in name else "")
            found.append(f"doctest case '{name}' has {entries_of[name]} ctest entries of its "
                         f"name, not 1{hint}")
    case_set = set(cases)
    for name, command, labels in runs_exe:
        if name not in case_set:
            found.append(f"ctest entry '{name}' runs {os.path.basename(exe)} but is not the name "
                         f"of a doctest case")
        n = selected_count(command)
        if n != 1:
            found.append(f"ctest entry '{name}' selects {n} doctest cases, not 1 (',' separates "
                         f"doctest filters, '*' and '?' are wildcards: reword the name)")
        for suite in sorted(suites_of.get(name, ())):
            if suite not in labels:
                found.append(f"ctest entry '{name}' lacks the label '{suite}' of its doctest "
                             f"suite (discovery looks suites up with the name unescaped: a ',' "
                             f"in the name loses the label; reword the name)")
    return found, len(cases), len(runs_exe)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--exe", required=True, help="the doctest executable")
    parser.add_argument("--build-dir", required=True, help="the directory ctest lists")
    parser.add_argument("--ctest", default="ctest", help="the ctest executable")
    args = parser.parse_args()
    found, n_cases, n_entries = problems(args.exe, args.build_dir, args.ctest)
    for problem in found:
        print("FAIL:", problem)
    if found:
        print(f"{len(found)} problems: ctest does not run every doctest case once under its own "
              f"name ({n_cases} cases, {n_entries} entries)")
        return 1
    print(f"{n_cases} doctest cases, each the one case of the ctest entry of its name")
    return 0


if __name__ == "__main__":
    sys.exit(main())
