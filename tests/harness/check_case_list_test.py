#!/usr/bin/env python3
"""Test of the guards that keep a green run honest: the test main and check_case_list.py.

The fixture (case_list_fixture.cpp, built with tests/main.cpp) holds one good name and one of each
bad kind. Its cases are discovered into a ctest file of their own by doctest's own discovery
script (doctestAddTests.cmake, as doctest_discover_tests runs it), in a scratch directory. Then:
- the fixture run with a filter that matches nothing fails, and one that matches a case passes;
- check_case_list.py fails on that directory and names each bad case, and none of the good ones.

Usage: check_case_list_test.py --fixture EXE --discover-script doctestAddTests.cmake
       --cmake CMAKE --ctest CTEST --workdir DIR
"""
import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))

failures = []


def expect(condition, what):
    print(("ok:   " if condition else "FAIL: ") + what)
    if not condition:
        failures.append(what)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fixture", required=True)
    parser.add_argument("--discover-script", required=True)
    parser.add_argument("--cmake", required=True)
    parser.add_argument("--ctest", required=True)
    parser.add_argument("--workdir", required=True)
    args = parser.parse_args()

    # The test main: no case selected is a failure with a message; one selected is a pass.
    none = subprocess.run([args.fixture, "--test-case=fixture: no such case"],
                          capture_output=True, text=True)
    expect(none.returncode != 0 and "selected no test case" in none.stderr,
           f"a run selecting no case fails with a message (exit {none.returncode})")
    one = subprocess.run([args.fixture, "--test-case=fixture: a plain name"],
                         capture_output=True, text=True)
    expect(one.returncode == 0, f"a run selecting one case passes (exit {one.returncode})")
    listing = subprocess.run([args.fixture, "--list-test-cases", "--test-case=no such case"],
                             capture_output=True, text=True)
    expect(listing.returncode == 0, "a listing that matches nothing is not a failed run")

    # Discovery into a ctest directory of its own, as doctest_discover_tests does it.
    shutil.rmtree(args.workdir, ignore_errors=True)
    os.makedirs(args.workdir)
    tests_file = os.path.join(args.workdir, "fixture_tests.cmake")
    subprocess.run([args.cmake, "-D", f"TEST_EXECUTABLE={args.fixture}", "-D", "TEST_EXECUTOR=",
                    "-D", f"TEST_WORKING_DIR={args.workdir}", "-D", "TEST_SPEC=",
                    "-D", "TEST_EXTRA_ARGS=", "-D", "TEST_PROPERTIES=", "-D", "TEST_ADD_LABELS=1",
                    "-D", "TEST_PREFIX=", "-D", "TEST_SUFFIX=", "-D", "TEST_LIST=fixture_TESTS",
                    "-D", "TEST_JUNIT_OUTPUT_DIR=", "-D", f"CTEST_FILE={tests_file}",
                    "-P", args.discover_script], check=True)
    with open(os.path.join(args.workdir, "CTestTestfile.cmake"), "w") as f:
        f.write(f'include("{tests_file}")\n')

    check = subprocess.run([sys.executable, os.path.join(HERE, "check_case_list.py"),
                            "--exe", args.fixture, "--build-dir", args.workdir,
                            "--ctest", args.ctest], capture_output=True, text=True)
    print(check.stdout, check.stderr)
    expect(check.returncode == 1, f"the check fails on the fixture (exit {check.returncode})")
    lines = check.stdout.splitlines()

    def reported(*parts):
        return any(line.startswith("FAIL:") and all(p in line for p in parts) for line in lines)

    expect(reported("'fixture: split here; and here' has 0 ctest entries", "';'"),
           "a name with ';' is reported as having no entry")
    expect(reported("entry 'fixture: split here'", "not the name of a doctest case"),
           "the first half of the split name is reported as an entry without a case")
    expect(reported("entry 'fixture: split here'", "selects 0 doctest cases"),
           "the first half of the split name is reported as selecting nothing")
    expect(reported("2 doctest cases are named 'fixture: twice'"), "a repeated name is reported")
    expect(reported("entry 'fixture: twice' selects 2"), "the entry of a repeated name runs two")
    expect(reported("entry 'fixture: any*' selects 2"), "a wildcard name selecting two is reported")
    expect(reported("entry 'fixture: slow, with a comma' lacks the label 'slow'"),
           "a suite case whose label discovery lost is reported")
    expect(not any("plain name" in line or "a slow one" in line or "any other" in line
                   for line in lines if line.startswith("FAIL:")),
           "the good names are not reported")
    if failures:
        print(f"{len(failures)} expectations failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
