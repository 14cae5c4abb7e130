#!/usr/bin/env python3
"""Run the GoogleTest cases that ctest registered, each test program in a few runs of many cases
(--jobs), instead of one process per case: CI's Windows suites, where every process is a Wine process, slow to start (and the
tool's tests start more of their own). Measured figures: README "Windows".

  gtest_once.py --build DIR --work DIR --rest FILE [--own-process REGEX] [--jobs N]
                [--timeout SECONDS] -- [CTEST SELECTION, e.g. -E REGEX]

The tests are those `ctest -N` lists for the selection. A test is taken here only when it is one
plain case: its command the emulator, a program and `--gtest_filter=Suite.Name` (and perhaps
`--gtest_also_run_disabled_tests`), its properties no more than those gtest_discover_tests gives
every case (working folder, the skip expression) and a time bound. Anything else (an environment,
a pass or fail expression, a test that is not a case, a name REGEX says needs a process of its
own) is left to ctest: FILE gets the ctest -R expression naming exactly those, empty if none.

Each program's cases are shared between N runs (round robin, so that a program of slow cases, such
as the tool's, keeps every core busy), N at a time; a run whose command line would pass Windows'
32,767 characters is split. Each run writes gtest's XML report, which alone says what ran: a case
missing from it counts as failed (a Wine program that ends early, with any status, writes none),
and so does every case of a run that ended otherwise than gtest ends (1 when a case failed, else
0). The failed cases run once more, together; one that fails again fails this script. The last
line says how many passed.
"""
import argparse
import concurrent.futures
import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree

# What gtest_discover_tests sets on every case, and the time bound (a run has its own, --timeout):
# nothing a run of many cases in one process would change.
PLAIN_PROPERTIES = {"WORKING_DIRECTORY", "SKIP_REGULAR_EXPRESSION", "TIMEOUT"}
GTEST_SKIP = ["\\[  SKIPPED \\]"]  # gtest_discover_tests' skip expression: the report says it
WINDOWS_COMMAND_LINE = 32767  # characters, the program's name and the separators included


def plain_case(test, own_process):
    """(emulator + program, working folder, gtest name) of a test that is a plain case, or None."""
    command = test.get("command") or []
    programs = [i for i, word in enumerate(command) if word.lower().endswith(".exe")]
    if not programs or own_process.search(test["name"]):
        return None
    arguments = command[programs[0] + 1:]
    if arguments[1:] not in ([], ["--gtest_also_run_disabled_tests"]):
        return None
    match = re.fullmatch(r"--gtest_filter=([^*?:-][^*?:]*)", arguments[0] if arguments else "")
    properties = {p["name"]: p["value"] for p in test.get("properties", [])}
    if not match or "WORKING_DIRECTORY" not in properties:
        return None
    if not set(properties) <= PLAIN_PROPERTIES:
        return None
    if properties.get("SKIP_REGULAR_EXPRESSION", GTEST_SKIP) != GTEST_SKIP:
        return None
    return tuple(command[:programs[0] + 1]), properties["WORKING_DIRECTORY"], match.group(1)


def runs_of(program, cases, shares):
    """The cases in `shares` runs, round robin, each split again if its command line would be
    too long."""
    runs = []
    for share in range(min(shares, len(cases))):
        run, length = [], 0
        # The program's Windows name (Z:\...), the report's argument and the flag, quoted and
        # separated, take less than 1,024 characters; each name takes its length and a colon.
        room = WINDOWS_COMMAND_LINE - 1024 - len(program[-1]) - len("--gtest_filter=")
        for case in cases[share::shares]:
            if run and length + len(case) + 1 > room:
                runs.append(run)
                run, length = [], 0
            run.append(case)
            length += len(case) + 1
        runs.append(run)
    return runs


def run_once(index, program, folder, cases, work, timeout):
    """Runs `cases` in one process; returns (passed, skipped, failed, what went wrong, seconds):
    failed is {case: gtest's message}, the last the run's status and end of output, or None."""
    report = work / f"run-{index}.xml"
    log = work / f"run-{index}.log"
    report.unlink(missing_ok=True)
    # gtest on Windows takes a path without a drive as relative to its folder: Wine's drive Z: is
    # the host's root.
    command = [*program, "--gtest_filter=" + ":".join(cases), "--gtest_also_run_disabled_tests",
               "--gtest_output=xml:Z:" + str(report.resolve())]
    started = time.monotonic()
    with open(log, "wb") as output:
        # A session of its own: past the time bound, the program and every process it started go.
        process = subprocess.Popen(command, cwd=folder, stdin=subprocess.DEVNULL, stdout=output,
                                   stderr=subprocess.STDOUT, start_new_session=True)
        try:
            status = process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            status = f"killed after {timeout} s"
    seconds = time.monotonic() - started
    results = {}  # case: "completed", "skipped", or its failures' messages
    try:
        cases_reported = list(ElementTree.parse(report).iter("testcase"))
    except (OSError, ElementTree.ParseError):
        cases_reported = None  # none, or cut short
    if cases_reported is not None:
        for case in cases_reported:
            name = f"{case.get('classname')}.{case.get('name')}"
            failures = [failure.get("message", "") for failure in case.iter("failure")]
            if failures:
                results[name] = "\n".join(failures)
            elif case.get("status") == "run":
                results[name] = case.get("result")
    unasked = sorted(set(results) - set(cases))
    if unasked:
        sys.exit(f"gtest_once: {program[-1]} ran cases not asked for: {', '.join(unasked[:5])}")
    passed = [case for case in cases if results.get(case) == "completed"]
    skipped = [case for case in cases if results.get(case) == "skipped"]
    failed = {case: results.get(case, "not run") for case in cases if case not in passed + skipped}
    problem = None
    # gtest exits with 1 when a case failed. Any other end (no report, a crash, a failure status
    # with no failed case) leaves every case of the run failed, even those the report says passed:
    # a program that fails on its way out, say.
    if cases_reported is None or status != (1 if failed else 0):
        failed.update((case, "its run failed") for case in passed + skipped)
        passed, skipped = [], []
        output = log.read_text(errors="replace").replace("\r", "").splitlines()
        report_said = "a report" if cases_reported is not None else "no report"
        problem = (f"exit status {status}, {report_said}; the end of its output:\n"
                   + "\n".join(output[-40:]))
    return passed, skipped, failed, problem, seconds


def run_all(jobs, workers, work, timeout, label):
    """jobs: [(program, folder, cases)], `workers` at a time; returns (passed, skipped, failed),
    failed as {(program, folder): [case]}."""
    passed, skipped, failed = [], [], {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(run_once, f"{label}{i}", *job, work, timeout): job
                   for i, job in enumerate(jobs)}
        for future in concurrent.futures.as_completed(futures):
            program, folder, cases = futures[future]
            ok, skip, failures, problem, seconds = future.result()
            passed += ok
            skipped += skip
            print(f"gtest_once: {pathlib.Path(program[-1]).name}: {len(cases)} cases, "
                  f"{len(ok)} passed, {len(skip)} skipped, {len(failures)} failed "
                  f"({seconds:.0f} s)", flush=True)
            if problem:
                print("  the run failed: " + problem.replace("\n", "\n    "), flush=True)
            unsaid = [case for case, message in failures.items()
                      if message in ("not run", "its run failed")]
            for case, message in failures.items():
                if case not in unsaid:
                    print(f"  failed: {case}: " + message.replace("\n", "\n    "), flush=True)
            if unsaid:
                print(f"  not run, or in a run that failed: {', '.join(unsaid)}", flush=True)
            if failures:
                failed.setdefault((program, folder), []).extend(failures)
    return passed, skipped, failed


def ctest_expression(names):
    """A ctest -R expression matching exactly these names (CMake's regex: '\\' before any other
    character matches that character)."""
    escaped = ("".join(c if c.isalnum() or c == "_" else "\\" + c for c in name) for name in names)
    return "^(" + "|".join(escaped) + ")$"


parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--build", required=True, help="the build folder (ctest --test-dir)")
parser.add_argument("--work", required=True, type=pathlib.Path, help="a folder for reports, logs")
parser.add_argument("--rest", required=True, type=pathlib.Path, help="a file for ctest's -R regex")
parser.add_argument("--own-process", default="(?!)", help="tests (ctest names) run alone by ctest")
parser.add_argument("--jobs", type=int, default=2, help="runs at a time, and runs per program")
parser.add_argument("--timeout", type=int, default=900, help="seconds one run may take")
parser.add_argument("selection", nargs="*", help="ctest's test selection (-R, -E, -L...)")
args = parser.parse_args()

listing = subprocess.run(["ctest", "--test-dir", args.build, "-N", "--show-only=json-v1",
                          *args.selection], check=True, stdout=subprocess.PIPE).stdout
tests = json.loads(listing)["tests"]
if not tests:
    sys.exit("gtest_once: ctest lists no test for this selection")  # as ctest --no-tests=error
own_process = re.compile(args.own_process)
groups, rest = {}, []
for test in tests:
    case = plain_case(test, own_process)
    if case is None:
        rest.append(test["name"])
    else:
        groups.setdefault(case[:2], []).append(case[2])
args.rest.write_text(ctest_expression(rest) if rest else "")
args.work.mkdir(parents=True, exist_ok=True)
taken = sum(len(cases) for cases in groups.values())
print(f"gtest_once: {taken} of the {len(tests)} tests are cases of {len(groups)} programs, each "
      f"run once; {len(rest)} left to ctest", flush=True)

# The programs with the most cases first: their runs start together and end about together.
jobs = [(program, folder, run)
        for (program, folder), cases in sorted(groups.items(), key=lambda group: -len(group[1]))
        for run in runs_of(program, cases, args.jobs)]
passed, skipped, again = run_all(jobs, args.jobs, args.work, args.timeout, "")
if again:
    # Under Wine a program now and then ends early (README "Windows"): what failed runs once more.
    count = sum(len(cases) for cases in again.values())
    print(f"gtest_once: running the {count} failed cases once more", flush=True)
    jobs = [(program, folder, run) for (program, folder), cases in again.items()
            for run in runs_of(program, cases, 1)]
    more_passed, more_skipped, again = run_all(jobs, args.jobs, args.work, args.timeout, "again-")
    passed += more_passed
    skipped += more_skipped
if len(passed) + len(skipped) + sum(len(c) for c in again.values()) != taken:
    raise SystemExit("gtest_once: the cases counted are not the cases taken")
if again:
    failed = sorted(case for cases in again.values() for case in cases)
    print(f"gtest_once: {len(failed)} cases failed twice: {', '.join(failed)}", file=sys.stderr)
    sys.exit(1)
print(f"gtest_once: {len(passed)} passed, {len(skipped)} skipped, of {taken} cases")
