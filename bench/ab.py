#!/usr/bin/env python3
"""Same-run A/B of two reproject_bench binaries (e.g. main's and a branch's), for a change's note.

    python3 bench/ab.py OLD_BINARY NEW_BINARY --filter REGEX [--rounds 6] [--repetitions 3]
                        [--min-time 0.05] [--old-env NAME=VALUE] [--new-env NAME=VALUE]

OLD and NEW may be the same binary run in two environments, e.g. AVX-512's two sRGB lookups:
    python3 bench/ab.py build/bench/reproject_bench build/bench/reproject_bench --filter ... \
        --old-env REPROJECT_SRGB_LOOKUP=permutes --new-env REPROJECT_SRGB_LOOKUP=gathers

The machines here are shared: a benchmark's time swings by tens of percent between consecutive
runs, so two runs made minutes apart say little. This script runs the two binaries in alternating
rounds (old, new, then new, old, ...), each round with --benchmark_repetitions, and prints per
benchmark two ratios new/old:

  * "median": the median over rounds of each round's median (what a typical run sees);
  * "min": the fastest repetition of all rounds (the least disturbed run; for compute-bound
    kernels the steadier figure on a noisy host).

Below 1 the new binary is faster. Run it once with the same binary as OLD and NEW first (an A/A):
the spread of those ratios is what this host's noise alone produces (on 2026-11-25, 6 rounds on
the 2-core Xeon: medians 0.81-1.21, minima 0.87-1.02), and an A/B ratio inside it shows nothing.
Quote both ratios, with the command, the machine, the load and the A/A spread.
"""

import argparse
import collections
import json
import os
import statistics
import subprocess


def run(binary, settings, args):
    """One run of a binary with the environment settings NAME=VALUE added: {benchmark name: [real
    time of each repetition, ms]}."""
    command = [binary, "--benchmark_filter=" + args.filter, "--benchmark_repetitions=%d" % args.repetitions,
               "--benchmark_min_time=%g" % args.min_time, "--benchmark_format=json"]
    env = dict(os.environ)
    env.update(setting.split("=", 1) for setting in settings)
    report = json.loads(subprocess.run(command, capture_output=True, text=True, check=True, env=env).stdout)
    times = collections.defaultdict(list)
    for entry in report["benchmarks"]:
        if entry.get("run_type") == "iteration":
            times[entry["run_name"]].append(entry["real_time"])
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--filter", required=True, help="a --benchmark_filter regex (quote it: '+' is an operator)")
    parser.add_argument("--rounds", type=int, default=6, help="alternating rounds (default 6)")
    parser.add_argument("--repetitions", type=int, default=3, help="repetitions per round (default 3)")
    parser.add_argument("--min-time", type=float, default=0.05, help="--benchmark_min_time per repetition")
    for label in ("old", "new"):
        parser.add_argument("--%s-env" % label, action="append", default=[], metavar="NAME=VALUE",
                            help="an environment variable for the %s binary's runs (repeatable)" % label)
    args = parser.parse_args()
    for setting in args.old_env + args.new_env:
        if "=" not in setting or setting.startswith("="):
            parser.error("--old-env/--new-env take NAME=VALUE, not %r" % setting)

    round_medians = {"old": collections.defaultdict(list), "new": collections.defaultdict(list)}
    fastest = {"old": {}, "new": {}}
    binaries = {"old": args.old, "new": args.new}
    settings = {"old": args.old_env, "new": args.new_env}
    for r in range(args.rounds):
        for label in ("old", "new") if r % 2 == 0 else ("new", "old"):
            for name, times in run(binaries[label], settings[label], args).items():
                round_medians[label][name].append(statistics.median(times))
                fastest[label][name] = min(fastest[label].get(name, float("inf")), min(times))

    names = sorted(set(round_medians["old"]) & set(round_medians["new"]))
    if not names:
        raise SystemExit("ab.py: no benchmark ran in both binaries (check --filter)")
    median_ratios, min_ratios = [], []
    print("load average %s; %d rounds x %d repetitions" % (" ".join("%.2f" % x for x in os.getloadavg()),
                                                           args.rounds, args.repetitions))
    print("%-64s %9s %9s %7s %9s %9s %7s" % ("benchmark (ms)", "old med", "new med", "ratio", "old min", "new min", "ratio"))
    for name in names:
        old_median = statistics.median(round_medians["old"][name])
        new_median = statistics.median(round_medians["new"][name])
        median_ratios.append(new_median / old_median)
        min_ratios.append(fastest["new"][name] / fastest["old"][name])
        print("%-64s %9.3f %9.3f %7.3f %9.3f %9.3f %7.3f" % (name, old_median, new_median, median_ratios[-1],
                                                             fastest["old"][name], fastest["new"][name], min_ratios[-1]))
    print("new/old over %d benchmarks: median of medians %.3f (%.3f-%.3f), median of minima %.3f (%.3f-%.3f)" % (
        len(names), statistics.median(median_ratios), min(median_ratios), max(median_ratios),
        statistics.median(min_ratios), min(min_ratios), max(min_ratios)))


if __name__ == "__main__":
    main()
