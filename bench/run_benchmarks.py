#!/usr/bin/env python3
"""Run reproject_bench and regenerate docs/PERFORMANCE.md from its results.

    python3 bench/run_benchmarks.py [--binary PATH] [--repetitions N] [--filter REGEX]
                                    [--min-time SECONDS] [--no-interleave] [--out JSON] [--doc MD]
    python3 bench/run_benchmarks.py --from-json JSON [--doc MD]   # rewrite the page only

The benchmark runs with --benchmark_repetitions=N --benchmark_report_aggregates_only=true
--benchmark_format=json; its JSON is kept (--out) with a "reproject_run" record added (the
command, CPU, compiler, load), so the page can be regenerated from it later. Every figure on the
page is the median of the N repetitions. The page's chart (docs/performance.png) is drawn with
matplotlib (Debian: python3-matplotlib); without it the page is written without the chart.
"""

import argparse
import datetime
import glob
import json
import os
import pathlib
import platform
import re
import shlex
import statistics
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = ["scanline", "march16", "single", "secant", "exact"]
SIZES = ["1280x720", "1920x1080", "3840x2160"]
FULL_HD = "1920x1080"
SEPARATIONS = [8, 32, 128]
THREADS = [1, 2]
GREY_SIZE = "512x512"
FLAT_METHODS = ["march16", "single", "secant", "exact"]  # targets: flat in resolution and separation
FLAT_TOLERANCE = 0.15
# Engine-native frames (`/<colour>+<depth>`, 1080p and 4K, colour output only), with their bytes per
# pixel (colour in + depth in + colour out); the first is the float baseline the others are compared with.
FORMATS = [("rgba32f+float", 36), ("rgba8+unorm24_s8", 12), ("rgba8_srgb+float", 12), ("rgba8_srgb+unorm24_s8", 12),
           ("rgba16f+float", 20), ("rgba8+unorm16", 10)]
FORMAT_SIZES = [FULL_HD, "3840x2160"]
FLOAT_FORMAT = FORMATS[0][0]
PACKED_FORMAT = "rgba8+unorm24_s8"  # the targets: an engine's RGBA8 back buffer and D24S8 depth
# Computation alone: the 1080p frame's middle 32 rows (`.../<colour>+<depth>/band:32`), in cache after
# the first call, for these formats and methods.
BAND_ROWS = 32
BAND = "/band:%d" % BAND_ROWS
BAND_FORMATS = [PACKED_FORMAT, FLOAT_FORMAT]
BAND_METHODS = ["single", "march16", "exact"]


# --- Running -----------------------------------------------------------------------------------

def find_binary():
    """build/bench/reproject_bench, else the most recently built build*/bench/reproject_bench."""
    preferred = os.path.join(REPO, "build", "bench", "reproject_bench")
    if os.access(preferred, os.X_OK):
        return preferred
    found = [p for p in glob.glob(os.path.join(REPO, "build*", "bench", "reproject_bench")) if os.access(p, os.X_OK)]
    if not found:
        sys.exit("run_benchmarks.py: no reproject_bench found under build*/bench; build it or pass --binary")
    return max(found, key=os.path.getmtime)


def read_text(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return ""


def cpu_info():
    """CPU model, logical CPUs, physical cores and whether AVX-512 is present, from /proc/cpuinfo."""
    text = read_text("/proc/cpuinfo")
    model = next(iter(re.findall(r"^model name\s*:\s*(.+)$", text, re.M)), platform.processor() or "unknown")
    logical = len(re.findall(r"^processor\s*:", text, re.M)) or os.cpu_count() or 0
    cores = set()
    for block in text.split("\n\n"):
        phys = re.search(r"^physical id\s*:\s*(\d+)", block, re.M)
        core = re.search(r"^core id\s*:\s*(\d+)", block, re.M)
        if phys and core:
            cores.add((phys.group(1), core.group(1)))
    flags = set(next(iter(re.findall(r"^flags\s*:\s*(.+)$", text, re.M)), "").split())
    return {
        "model": model.strip(),
        "logical_cpus": logical,
        "physical_cores": len(cores) or logical,
        "avx2": "avx2" in flags,
        "avx512f": "avx512f" in flags,
    }


def compiler_info(binary):
    """The C++ compiler and flags from the build directory's CMakeCache.txt."""
    build_dir = os.path.dirname(os.path.dirname(os.path.abspath(binary)))
    cache = read_text(os.path.join(build_dir, "CMakeCache.txt"))

    def entry(key):
        match = re.search(r"^" + re.escape(key) + r":[A-Z]+=(.*)$", cache, re.M)
        return match.group(1).strip() if match else ""

    compiler = entry("CMAKE_CXX_COMPILER") or "c++"
    build_type = entry("CMAKE_BUILD_TYPE")
    flags = " ".join(x for x in [entry("CMAKE_CXX_FLAGS"), entry("CMAKE_CXX_FLAGS_" + build_type.upper())] if x)
    try:
        version = subprocess.run([compiler, "--version"], capture_output=True, text=True, check=False).stdout
        version = version.splitlines()[0] if version else compiler
    except OSError:
        version = compiler
    return {"compiler": version, "build_type": build_type or "unknown", "flags": flags, "build_dir": build_dir}


def source_revision():
    """The commit the library was built from, and whether the working tree had changes on top."""
    def git(*args):
        try:
            # Only trailing newlines: porcelain lines start with a status column that may be a space.
            return subprocess.run(["git", "-C", REPO] + list(args), capture_output=True, text=True,
                                  check=False).stdout.rstrip("\n")
        except OSError:
            return ""
    commit = git("rev-parse", "--short", "HEAD")
    if not commit:
        return "unknown"
    # What the benchmark links: the library, its headers and the scenes (scene/). New files count
    # too (a header added to the library is part of what was measured).
    changed = [line[3:] for line in git("status", "--porcelain", "--", "include", "src", "kernels", "scene",
                                        "CMakeLists.txt").splitlines()]
    return commit + (" + uncommitted changes to " + ", ".join(changed) if changed else "")


def load_average():
    parts = read_text("/proc/loadavg").split()
    return " ".join(parts[:3]) if parts else "unknown"


def run(args):
    binary = os.path.abspath(args.binary or find_binary())
    out = os.path.abspath(args.out or os.path.join(os.path.dirname(binary), "reproject_bench.json"))
    command = [binary, "--benchmark_repetitions=%d" % args.repetitions, "--benchmark_report_aggregates_only=true",
               "--benchmark_format=json", "--benchmark_min_time=%g" % args.min_time]
    if args.interleave:
        # Each benchmark's repetitions are spread over the whole run, so a burst of load from
        # another user of this shared machine spoils one repetition, which the median drops.
        command.append("--benchmark_enable_random_interleaving=true")
    if args.filter:
        command.append("--benchmark_filter=" + args.filter)

    listing = subprocess.run([binary, "--benchmark_list_tests"] + ([ "--benchmark_filter=" + args.filter] if args.filter else []),
                             capture_output=True, text=True, check=True).stdout.split()
    print("run_benchmarks.py: %d benchmarks x %d repetitions; JSON -> %s" % (len(listing), args.repetitions, out),
          flush=True)
    print("  " + " ".join(shlex.quote(c) for c in command), flush=True)
    if args.wait_idle is not None:
        # On a shared machine a run that starts during someone's build measures the build.
        deadline = time.time() + args.wait_max
        while float(load_average().split()[0]) >= args.wait_idle and time.time() < deadline:
            time.sleep(15)
        print("run_benchmarks.py: load average %s at start" % load_average(), flush=True)
    load_before = load_average()
    started = time.time()
    with open(out, "w", encoding="utf-8") as f:
        result = subprocess.run(command, stdout=f, check=False)
    elapsed = time.time() - started
    if result.returncode != 0:
        sys.exit("run_benchmarks.py: reproject_bench exited with %d (partial JSON in %s)" % (result.returncode, out))

    with open(out, encoding="utf-8") as f:
        data = json.load(f)
    data["reproject_run"] = {
        "script_command": "python3 " + " ".join(shlex.quote(a) for a in [os.path.relpath(sys.argv[0], REPO)] + sys.argv[1:]),
        "bench_command": " ".join(shlex.quote(c) for c in command),
        "repetitions": args.repetitions,
        "min_time": args.min_time,
        "filter": args.filter or "",
        "interleave": args.interleave,
        "cpu": cpu_info(),
        "build": compiler_info(binary),
        "revision": source_revision(),
        "load_before": load_before,
        "load_after": load_average(),
        "elapsed_s": round(elapsed, 1),
        "finished": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
    }
    with open(out, "w", encoding="utf-8") as f:
        json.dump(data, f, indent=1)
    print("run_benchmarks.py: done in %.0f s" % elapsed, flush=True)
    return data, out


# --- Results ---------------------------------------------------------------------------------------

class Results:
    """Median (and spread) of every benchmark, keyed by its name."""

    def __init__(self, data):
        self.rows = {}
        self.errors = {}
        for b in data.get("benchmarks", []):
            name = b.get("run_name") or b["name"]
            if b.get("error_occurred"):
                self.errors[name] = b.get("error_message", "error")
                continue
            kind = b.get("aggregate_name") if b.get("run_type") == "aggregate" else "median"
            row = self.rows.setdefault(name, {})
            if kind in ("median", "cv"):
                row[kind] = b
            if b.get("run_type") != "aggregate":
                row["repetitions"] = row.get("repetitions", 0) + 1

    def get(self, name):
        row = self.rows.get(name)
        return row.get("median") if row else None

    def ms(self, name):
        b = self.get(name)
        if not b:
            return None
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
        return b["real_time"] * scale

    def cpu_ms(self, name):
        b = self.get(name)
        if not b:
            return None
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
        return b["cpu_time"] * scale

    def mpix(self, name):
        b = self.get(name)
        return b["items_per_second"] / 1e6 if b and "items_per_second" in b else None

    def gbs(self, name):
        b = self.get(name)
        return b["bytes_per_second"] / 1e9 if b and "bytes_per_second" in b else None

    def cv(self, name):
        """Coefficient of variation of the time over the repetitions (None with one repetition)."""
        row = self.rows.get(name)
        if not row or "cv" not in row:
            return None
        return row["cv"]["real_time"]


def name(method, arch, size, threads, suffix=""):
    return "%s/%s/%s/threads:%d%s" % (method, arch, size, threads, suffix)


def roofline(size, threads, suffix=""):
    return "roofline/%s/threads:%d%s" % (size, threads, suffix)


def ratio(x, y):
    return x / y if x is not None and y not in (None, 0) else None


def fmt(value, digits=1, suffix=""):
    if value is None:
        return "–"
    return ("%." + str(digits) + "f%s") % (value, suffix)


def pct(value):
    return "–" if value is None else "%+.0f %%" % (100.0 * value)


def spread(values):
    """Largest deviation from the median, as a fraction: how far from flat a series is."""
    values = [v for v in values if v is not None]
    if len(values) < 2:
        return None
    mid = statistics.median(values)
    return max(abs(v / mid - 1.0) for v in values)


def table(header, rows, align=None):
    align = align or ["l"] + ["r"] * (len(header) - 1)
    marks = {"l": ":--", "r": "--:"}
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(marks[a] for a in align) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


# --- The chart ---------------------------------------------------------------------------------------

def draw_chart(r, present, cpu_model, png_path):
    """Mpix/s per method and arch at 1 and 2 threads (1080p planar RGBA), the roofline marked.
    Returns False (and says why) when matplotlib is missing."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("run_benchmarks.py: matplotlib not found (apt-get install python3-matplotlib): no chart", file=sys.stderr)
        return False
    colors = {"scalar": "#9e9e9e", "sse": "#64b5f6", "avx2": "#1e88e5", "avx512": "#0d47a1"}
    fig, axes = plt.subplots(1, len(THREADS), figsize=(11, 4.2), sharey=True)
    width = 0.8 / max(1, len(present))
    top = 0.0
    for ax, threads in zip(axes, THREADS):
        for k, arch in enumerate(present):
            values = [r.mpix(name(m, arch, FULL_HD, threads)) or 0.0 for m in METHODS]
            xs = [i + (k - (len(present) - 1) / 2) * width for i in range(len(METHODS))]
            bars = ax.bar(xs, values, width, label=arch, color=colors.get(arch, "#444444"))
            ax.bar_label(bars, labels=["%.0f" % v if v else "" for v in values], fontsize=6, padding=1)
            top = max(top, max(values))
        roof = r.mpix(roofline(FULL_HD, threads))
        if roof:
            ax.axhline(roof, color="#c62828", linestyle="--", linewidth=1.2)
            ax.text(len(METHODS) - 0.5, roof, "roofline %.0f Mpix/s (memory speed)" % roof, color="#c62828",
                    ha="right", va="bottom", fontsize=8)
            top = max(top, roof)
        ax.set_xticks(range(len(METHODS)))
        ax.set_xticklabels(METHODS)
        ax.set_title("%d thread%s" % (threads, "s" if threads > 1 else ""))
        ax.grid(axis="y", alpha=0.3)
    axes[0].set_ylabel("Mpix/s (1920x1080, planar RGBA; higher is better)")
    axes[0].set_ylim(0, top * 1.12)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, title="instruction set", fontsize=8, loc="lower center", ncol=len(labels))
    fig.suptitle("reproject: speed per method and instruction set — %s" % cpu_model, fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(png_path, dpi=110)
    plt.close(fig)
    return True


# --- The page --------------------------------------------------------------------------------------

def write_page(data, json_path, doc_path):
    r = Results(data)
    run_info = data.get("reproject_run", {})
    context = data.get("context", {})
    cpu = run_info.get("cpu") or cpu_info()
    build = run_info.get("build") or (compiler_info(context["executable"]) if context.get("executable") else {})
    # The instruction sets in the library's order, as the benchmark binary lists the ones it ran.
    archs = (context.get("reproject_archs") or "").split(",")
    present = [a for a in archs if any(k.split("/")[1:2] == [a] for k in r.rows)]
    simd = [a for a in present if a != "scalar"]
    # The engine-format cases run on AVX2 and on the binary's best set (AVX-512 where the CPU has it),
    # and their targets hold for each of them, not for the better of the two.
    binary_archs = [a for a in archs if a] or present
    format_archs = (["avx2"] if "avx2" in binary_archs else []) + [a for a in binary_archs[-1:] if a != "avx2"]

    def best_arch(method, size=FULL_HD, threads=1, suffix=""):
        """The arch with the highest median Mpix/s for this case (scalar only if it is alone)."""
        candidates = [(r.mpix(name(method, a, size, threads, suffix)), a) for a in (simd or present)]
        candidates = [c for c in candidates if c[0] is not None]
        return max(candidates)[1] if candidates else None

    out = []
    w = out.append
    w("# Performance")
    w("")
    w("Generated by `bench/run_benchmarks.py` from the JSON of one run of `reproject_bench`; do not edit by")
    w("hand, rerun the script. Every figure is the **median** of the repetitions; times are wall-clock")
    w("(each benchmark times its own loop). Mpix/s counts target pixels (both eyes for `pair_`). \"÷ roofline\" is the")
    w("kernel's time divided by the time of `roofline` at the same size and thread count: a plain")
    w("row copy of exactly the bytes one eye must touch (read depth + colour, write colour + depth +")
    w("status: 41 B/px for RGBA, 17 B/px for one grey plane; for the engine-format cases, read colour + depth")
    w("and write colour, in their own section), i.e. the memory-speed limit.")
    w("")
    w("Benchmark names are those of `bench/bench_reproject.cpp` (`<method>/<arch>/<W>x<H>/threads:<n>[/sep:<px>|/rgba|/grey]`,")
    w("`<method>/<arch>/<W>x<H>/threads:<n>/<colour>+<depth>[/band:32]`, `pair_<method>/...`, `roofline/...`). Times and")
    w("rates are wall-clock.")
    w("Rerun a subset with e.g. `python3 bench/run_benchmarks.py --filter 'march16/avx2'` (the page then shows")
    w("only what ran).")
    w("")
    w("## Machine and run")
    w("")
    finished = run_info.get("finished") or context.get("date", "unknown")
    w("* Date: %s" % finished)
    w("* CPU: %s — %d logical CPUs, %d physical cores%s" % (
        cpu.get("model"), cpu.get("logical_cpus", 0), cpu.get("physical_cores", 0),
        ", %s MHz" % context["mhz_per_cpu"] if context.get("mhz_per_cpu") else ""))
    caches = context.get("caches") or []
    if caches:
        w("* Caches: " + ", ".join("L%d %s %d KiB%s" % (c["level"], c["type"].lower(), c["size"] // 1024,
                                                          " ×%d" % (context.get("num_cpus", 1) // c["num_sharing"])
                                                          if c.get("num_sharing") else "") for c in caches))
    w("* Instruction sets: %s. %s" % (
        ", ".join(present) or "none",
        "This machine has AVX2 but no AVX-512: the AVX-512 rows are absent (not registered); take them "
        "on a machine that has it." if cpu.get("avx2") and not cpu.get("avx512f") else
        ("AVX-512 present: every table has its AVX-512 rows beside the AVX2 ones (each set is run "
         "explicitly, `Options::arch`, in the same binary)." if cpu.get("avx512f") else "No AVX2.")))
    if run_info.get("revision"):
        w("* Source: %s" % run_info["revision"])
    w("* Compiler: %s, %s build%s" % (build.get("compiler", "unknown"), build.get("build_type", "unknown"),
                                       " (`%s`)" % build["flags"] if build.get("flags") else ""))
    if context.get("reproject_scene"):
        w("* Frame: built-in scene `%s`, centre view; %s" % (context["reproject_scene"], context.get("reproject_stereo", "")))
    w("* Command: `%s`" % run_info.get("script_command", "python3 bench/run_benchmarks.py"))
    if run_info.get("bench_command"):
        w("* Which ran: `%s`" % run_info["bench_command"])
    w("* JSON: `%s`%s" % (os.path.relpath(json_path, REPO) if json_path.startswith(REPO) else json_path,
                          ", %s s" % run_info["elapsed_s"] if "elapsed_s" in run_info else ""))
    others = sorted(p for p in glob.glob(os.path.join(os.path.dirname(os.path.abspath(doc_path)), "PERFORMANCE*.md"))
                    if os.path.abspath(p) != os.path.abspath(doc_path))
    if others:
        w("* The same benchmarks on other processors, each page from its own run (revision and date on it): %s."
          " Speed choices can differ between processors: see \"Measured design choices\"." %
          ", ".join("[%s](%s)" % (os.path.basename(p), os.path.basename(p)) for p in others))

    # Contention: with one thread the calling thread's CPU time equals the wall time unless the
    # scheduler took the core away; the ratio says how much of the wall time was someone else's.
    single = [n for n in r.rows if n.endswith("/threads:1") and not n.startswith("roofline")]
    busy = [ratio(r.cpu_ms(n), r.ms(n)) for n in single]
    busy = [b for b in busy if b is not None]
    load = "%s before, %s after" % (run_info.get("load_before", "?"), run_info.get("load_after", "?"))
    if busy:
        w("* Load: %s (load average). Median CPU time ÷ wall time of the 1-thread kernels: %.2f "
          "(1.00 on an idle machine; lower means the core was shared during the run, and wall times are "
          "inflated by that much)." % (load, statistics.median(busy)))
    cvs = [r.cv(n) for n in r.rows if r.cv(n) is not None]
    if cvs:
        w("* Noise: median coefficient of variation over the repetitions %.1f %%, worst %.1f %%." % (
            100 * statistics.median(cvs), 100 * max(cvs)))
    w("")
    os.makedirs(os.path.dirname(os.path.abspath(doc_path)), exist_ok=True)
    # The chart beside the page, named after it (PERFORMANCE.md: performance.png), so that pages of
    # other processors (PERFORMANCE_<CPU>.md, each from its own JSON) keep their own.
    doc_stem = os.path.splitext(os.path.basename(doc_path))[0]
    png = os.path.join(os.path.dirname(os.path.abspath(doc_path)), doc_stem.lower() + ".png")
    if draw_chart(r, present, cpu.get("model", "unknown CPU"), png):
        w("![Mpix/s per method and instruction set at 1 and 2 threads, 1080p planar RGBA, with the roofline](%s)"
          % os.path.basename(png))
        w("")
        w("*The chart: 1080p planar RGBA, median Mpix/s of every method on every instruction set at 1 and 2 "
          "threads; the dashed line is the roofline (a plain copy of the same bytes). Measured on %s.*" %
          cpu.get("model", "unknown CPU"))
        w("")

    # Threads: honoured or not. The calling thread's CPU time halves when the library really
    # splits the rows over two threads (it does half the rows), whatever the contention.
    scal = [ratio(r.mpix(name(m, a, FULL_HD, 2)), r.mpix(name(m, a, FULL_HD, 1))) for m in METHODS for a in present]
    scal = [s for s in scal if s is not None]
    cpu_split = [ratio(r.cpu_ms(name(m, a, FULL_HD, 2)), r.cpu_ms(name(m, a, FULL_HD, 1)))
                 for m in METHODS for a in present]
    cpu_split = [c for c in cpu_split if c is not None]
    threads_note = None
    if scal and cpu_split:
        honoured = statistics.median(cpu_split) < 0.8
        if honoured:
            threads_note = ("`Options::threads` is honoured in this build: at threads:2 the calling thread's CPU "
                            "time is %.2f× its 1-thread CPU time (median over methods and archs), i.e. it does "
                            "about half the rows; the wall-clock 2-thread scaling is %.2f× (median)." %
                            (statistics.median(cpu_split), statistics.median(scal)))
            if busy and statistics.median(busy) < 0.9:
                threads_note += (" This machine has %d cores and was shared during the run (see Load above): "
                                 "a 2-thread run needs both cores free at once, so its wall time, and every "
                                 "2-thread figure below, is a pessimistic bound." % cpu.get("physical_cores", 0))
        else:
            threads_note = ("**`Options::threads` was not honoured by the library this run used** (threads were "
                            "still being implemented): every call ran on one thread, so the threads:2 rows "
                            "measure 1-thread speed (median 2-thread ÷ 1-thread %.2f×; calling-thread CPU "
                            "time ratio %.2f×). The 2-thread targets below are therefore missed for that "
                            "reason, not measured against a real 2-thread kernel; rerun this script once "
                            "threads land. The roofline's threads:2 rows do use two threads (std::threads of "
                            "the benchmark)." % (statistics.median(scal), statistics.median(cpu_split)))
    if threads_note:
        w("> " + threads_note)
        w("")

    # --- Targets ---
    targets = []

    def target(text, value_text, met):
        targets.append((text, value_text, "met" if met else ("missed" if met is not None else "no data")))

    def information(text, value_text):
        """A row of the targets table that is a direction, not a pass/fail: not counted."""
        targets.append((text, value_text, "information"))

    for method, limit in (("single", 1.2), ("march16", 1.2), ("secant", 2.0), ("exact", 2.0)):
        arch = best_arch(method, threads=2)
        value = ratio(r.ms(name(method, arch, FULL_HD, 2)), r.ms(roofline(FULL_HD, 2))) if arch else None
        target("%s, 2 threads, 1080p: time ≤ %.1f× roofline" % (method, limit),
               "%s× (%s)" % (fmt(value, 2), arch), None if value is None else value <= limit)
    arch = best_arch("march16")
    value = ratio(r.mpix(name("march16", arch, FULL_HD, 1)), r.mpix(name("march16", "scalar", FULL_HD, 1))) if arch else None
    target("march16, best arch, 1 thread, 1080p: ≥ 5× scalar", "%s× (%s)" % (fmt(value, 2), arch),
           None if value is None else value >= 5.0)
    arch = best_arch("march16", GREY_SIZE, 1, "/grey")
    value = ratio(r.mpix(name("march16", arch, GREY_SIZE, 1, "/grey")),
                  r.mpix(name("march16", "scalar", GREY_SIZE, 1, "/grey"))) if arch else None
    target("/grey march16 (512x512, in cache), best arch: ≥ 10× scalar", "%s× (%s)" % (fmt(value, 2), arch),
           None if value is None else value >= 10.0)
    if "avx512" in present:
        value = ratio(r.mpix(name("march16", "avx512", GREY_SIZE, 1, "/grey")),
                      r.mpix(name("march16", "scalar", GREY_SIZE, 1, "/grey")))
        target("/grey march16 (512x512, in cache), AVX-512: ≥ 10× scalar", "%s×" % fmt(value, 2),
               None if value is None else value >= 10.0)
        for method in METHODS:
            for threads in THREADS:
                t512, t2 = r.ms(name(method, "avx512", FULL_HD, threads)), r.ms(name(method, "avx2", FULL_HD, threads))
                value = ratio(t512, t2)
                target("%s, 1080p, %d thread%s: AVX-512 time ≤ AVX2 time" % (method, threads, "s" if threads > 1 else ""),
                       "%s× (%s vs %s ms)" % (fmt(value, 2), fmt(t512, 2), fmt(t2, 2)),
                       None if value is None else value <= 1.0)
    for arch in format_archs:
        for threads in THREADS:
            value = ratio(r.ms(name("exact", arch, FULL_HD, threads, "/near:fixed")), r.ms(name("exact", arch, FULL_HD, threads)))
            target("exact, %s, 1080p, %d thread%s: fixed near limit |a|/2 ≤ 1.1× the frame's own" % (
                       arch, threads, "s" if threads > 1 else ""),
                   "%s×" % fmt(value, 2), None if value is None else value <= 1.1)
    for method in METHODS:
        for threads, limit in ((1, 0.75), (2, 0.8)):
            arch = best_arch(method, threads=threads)
            value = ratio(r.ms(name("pair_" + method, arch, FULL_HD, threads)),
                          r.ms(name("pair_" + method, arch, FULL_HD, threads, "/two_calls"))) if arch else None
            target("pair_%s, 1080p, %d thread%s: ≤ %.2f× two single-eye calls" % (method, threads, "s" if threads > 1 else "", limit),
                   "%s× (%s)" % (fmt(value, 2), arch), None if value is None else value <= limit)
    for method in METHODS:
        arch = best_arch(method, threads=2)
        value = ratio(r.mpix(name(method, arch, FULL_HD, 2)), r.mpix(name(method, arch, FULL_HD, 1))) if arch else None
        target("%s, 1080p: 2 threads ≥ 1.85× 1 thread" % method, "%s× (%s)" % (fmt(value, 2), arch),
               None if value is None else value >= 1.85)
    for method in FLAT_METHODS:
        arch = best_arch(method)
        for threads in THREADS:
            values = [r.mpix(name(method, arch, s, threads)) for s in SIZES] if arch else []
            value = spread(values)
            target("%s, %d thread%s: Mpix/s within ±15 %% from 720p to 4K" % (method, threads, "s" if threads > 1 else ""),
                   "%s (%s: %s Mpix/s)" % (pct(value), arch, " / ".join(fmt(v) for v in values)),
                   None if value is None else value <= FLAT_TOLERANCE)
    for method in FLAT_METHODS:
        arch = best_arch(method)
        for threads in THREADS:
            values = [r.mpix(name(method, arch, FULL_HD, threads, "/sep:%d" % s)) for s in SEPARATIONS] if arch else []
            value = spread(values)
            target("%s, %d thread%s: Mpix/s within ±15 %% across separations 8–128 px" % (
                method, threads, "s" if threads > 1 else ""),
                "%s (%s: %s Mpix/s)" % (pct(value), arch, " / ".join(fmt(v) for v in values)),
                None if value is None else value <= FLAT_TOLERANCE)

    # Engine-native formats (issue 23), on AVX2 and on the best arch each: rgba8+unorm24_s8 against
    # its own roofline and against the float path on the same arch.
    def format_figures(method, arch, fmt_name, size=FULL_HD, threads=2):
        """(ms, time ÷ the format's own roofline, speed-up over the same method and arch on the float path)."""
        ms = r.ms(name(method, arch, size, threads, "/" + fmt_name))
        float_ms = r.ms(name(method, arch, size, threads, "/" + FLOAT_FORMAT))
        return ms, ratio(ms, r.ms(roofline(size, threads, "/" + fmt_name))), ratio(float_ms, ms)

    format_targets = {}  # (method, arch, format) -> [(text, verdict)], for the 1080p formats tables

    def format_target(method, arch, fmt_name, text, value_text, met):
        target(text, value_text, met)
        format_targets.setdefault((method, arch, fmt_name), []).append((text.split(": ")[-1], targets[-1][2]))

    for arch in format_archs:
        for method in ("single", "march16"):
            _, value, speedup = format_figures(method, arch, PACKED_FORMAT)
            format_target(method, arch, PACKED_FORMAT,
                          "%s on %s, %s, 2 threads, 1080p: time ≤ 1.5× its own roofline" % (method, PACKED_FORMAT, arch),
                          "%s×" % fmt(value, 2), None if value is None else value <= 1.5)
            format_target(method, arch, PACKED_FORMAT,
                          "%s on %s, %s, 2 threads, 1080p: ≥ 2.0× faster than on %s, same arch" % (
                              method, PACKED_FORMAT, arch, FLOAT_FORMAT),
                          # three decimals: a ratio just under its limit must not print as the limit
                          "%s×" % fmt(speedup, 3), None if speedup is None else speedup >= 2.0)
    for arch in format_archs:
        for label, suffix in ((FLOAT_FORMAT, "/" + FLOAT_FORMAT), ("planar RGBA", "")):
            value = ratio(r.ms(name("march16", arch, FULL_HD, 2, suffix)), r.ms(roofline(FULL_HD, 2, suffix)))
            information("march16 on the float path (%s), %s, 2 threads, 1080p: time ÷ its roofline, against 1.2× "
                        "(a direction, not a pass/fail)" % (label, arch),
                        "%s×%s" % (fmt(value, 2), "" if value is None else " (%s 1.2×)" % ("above" if value > 1.2 else "within")))

    w("## Targets")
    w("")
    w("\"Best arch\" is the instruction set with the highest median Mpix/s for that method in that case; a")
    w("target that names its arch holds for that arch alone. A flatness figure is the largest deviation of")
    w("the three Mpix/s values from their median. Rows marked \"information\" show a figure against a direction,")
    w("not a target, and are not counted.")
    w("")
    w(table(["target", "measured", "verdict"], [(t, v, m if m == "information" else "**%s**" % m) for t, v, m in targets],
            ["l", "l", "l"]))
    met = sum(1 for t in targets if t[2] == "met")
    counted = sum(1 for t in targets if t[2] != "information")
    w("")
    w("%d of %d targets met." % (met, counted))
    w("")

    # --- 1080p planar RGBA ---
    w("## 1080p, planar RGBA (4 float planes)")
    w("")
    w("Measured on %s (every table on this page comes from this one run on this CPU)." % cpu.get("model", "unknown CPU"))
    w("")
    rf1, rf2 = roofline(FULL_HD, 1), roofline(FULL_HD, 2)

    def cpu_mpix(n):
        """Mpix/s from the calling thread's CPU time: what a 1-thread run would reach on an idle core."""
        cpu_ms = r.cpu_ms(n)
        return r.mpix(n) * r.ms(n) / cpu_ms if cpu_ms and r.mpix(n) else None

    w("Roofline: %s Mpix/s (%s GB/s, %s ms) at 1 thread, %s Mpix/s (%s GB/s, %s ms) at 2 threads." % (
        fmt(r.mpix(rf1)), fmt(r.gbs(rf1), 1), fmt(r.ms(rf1), 2), fmt(r.mpix(rf2)), fmt(r.gbs(rf2), 1), fmt(r.ms(rf2), 2)))
    w("\"1T on CPU time\" recomputes the 1-thread rate from the calling thread's CPU time instead of the")
    w("wall time: on this shared machine it is the rate the kernel reaches when it has the core to itself.")
    w("Every other column, and every target, uses wall time. The `scalar` rows are what `Arch::scalar` runs")
    w("on this CPU: the scalar references built with AVX2 + FMA flags at -O3 (hardware fma and floor; the")
    w("compiler may vectorise their simplest loops), i.e. a user's own scalar port built with -march=native.")
    w("")
    rows = []
    for method in METHODS:
        for arch in present:
            n1, n2 = name(method, arch, FULL_HD, 1), name(method, arch, FULL_HD, 2)
            s1, s2 = name(method, "scalar", FULL_HD, 1), name(method, "scalar", FULL_HD, 2)
            rows.append([method, arch, fmt(r.ms(n1), 2), fmt(r.mpix(n1)), fmt(cpu_mpix(n1)), fmt(r.mpix(n2)),
                         fmt(ratio(r.mpix(n1), r.mpix(s1)), 2), fmt(ratio(r.mpix(n2), r.mpix(s2)), 2),
                         fmt(ratio(r.mpix(n2), r.mpix(n1)), 2),
                         fmt(ratio(r.ms(n1), r.ms(rf1)), 2), fmt(ratio(r.ms(n2), r.ms(rf2)), 2)])
    w(table(["method", "arch", "ms 1T", "Mpix/s 1T", "1T on CPU time", "Mpix/s 2T", "× scalar 1T", "× scalar 2T",
             "2T ÷ 1T", "÷ roofline 1T", "÷ roofline 2T"], rows, ["l", "l"] + ["r"] * 9))
    w("")

    # --- Resolution ---
    w("## Cost against resolution (planar RGBA)")
    w("")
    w("The default stereo scales with the width (parallax at infinity a = 1.5 % of it: 19.2 / 28.8 / 57.6 px),")
    w("as a game's would, so a method whose cost follows the parallax range (`scanline`) slows down")
    w("per pixel at 4K while the O(1) ones should stay flat.")
    w("")
    for threads in THREADS:
        rows = []
        for method in METHODS:
            for arch in present:
                values = [r.mpix(name(method, arch, s, threads)) for s in SIZES]
                rows.append([method, arch] + [fmt(v) for v in values] + [pct(spread(values)),
                            fmt(ratio(r.ms(name(method, arch, SIZES[-1], threads)), r.ms(roofline(SIZES[-1], threads))), 2)])
        rf = [r.mpix(roofline(s, threads)) for s in SIZES]
        rows.append(["roofline", "—"] + [fmt(v) for v in rf] + [pct(spread(rf)), "1.00"])
        w("**%d thread%s** — Mpix/s" % (threads, "s" if threads > 1 else ""))
        w("")
        w(table(["method", "arch", "720p", "1080p", "4K", "flatness", "4K ÷ roofline"], rows, ["l", "l"] + ["r"] * 5))
        w("")

    # --- Separation ---
    w("## Cost against separation (1080p, planar RGBA)")
    w("")
    w("Parallax at infinity a = 8, 32 and 128 px, convergence as the scene's (zero parallax mid-range), so")
    w("the search range grows with a. `scanline` walks the range a column at a time: its cost grows with")
    w("it (\"128 ÷ 8\" is its time ratio); the other methods should not care.")
    w("")
    for threads in THREADS:
        rows = []
        for method in METHODS:
            for arch in present:
                names = [name(method, arch, FULL_HD, threads, "/sep:%d" % s) for s in SEPARATIONS]
                values = [r.mpix(n) for n in names]
                rows.append([method, arch] + [fmt(v) for v in values] +
                            [pct(spread(values)), fmt(ratio(r.ms(names[-1]), r.ms(names[0])), 2)])
        w("**%d thread%s** — Mpix/s" % (threads, "s" if threads > 1 else ""))
        w("")
        w(table(["method", "arch", "a = 8", "a = 32", "a = 128", "flatness", "time 128 ÷ 8"], rows,
                ["l", "l"] + ["r"] * 5))
        w("")

    # --- Grey, in cache ---
    w("## One grey plane at 512x512, in cache (`/grey`, march16, 1 thread)")
    w("")
    w("17 B/px × 512² = 4.5 MB: the whole working set stays in L2/L3, so this isolates the kernels'")
    w("arithmetic from the memory wall.")
    w("")
    rows = []
    rg = roofline(GREY_SIZE, 1, "/grey")
    for arch in present:
        n = name("march16", arch, GREY_SIZE, 1, "/grey")
        rows.append([arch, fmt(r.ms(n), 3), fmt(r.mpix(n)),
                     fmt(ratio(r.mpix(n), r.mpix(name("march16", "scalar", GREY_SIZE, 1, "/grey"))), 2),
                     fmt(ratio(r.ms(n), r.ms(rg)), 1)])
    rows.append(["roofline (copy)", fmt(r.ms(rg), 3), fmt(r.mpix(rg)), "–", "1.0"])
    w(table(["arch", "ms", "Mpix/s", "× scalar", "÷ roofline"], rows))
    w("")

    # --- Interleaved RGBA ---
    w("## Interleaved RGBA (`/rgba`, 1080p)")
    w("")
    w("Same bytes as planar RGBA (41 B/px); \"÷ planar\" is the interleaved Mpix/s over the planar one.")
    w("")
    rows = []
    for method in METHODS:
        for arch in present:
            n1, n2 = name(method, arch, FULL_HD, 1, "/rgba"), name(method, arch, FULL_HD, 2, "/rgba")
            rows.append([method, arch, fmt(r.mpix(n1)), fmt(r.mpix(n2)),
                         fmt(ratio(r.mpix(n1), r.mpix(name(method, arch, FULL_HD, 1))), 2),
                         fmt(ratio(r.mpix(n2), r.mpix(name(method, arch, FULL_HD, 2))), 2),
                         fmt(ratio(r.ms(n1), r.ms(rf1)), 2), fmt(ratio(r.ms(n2), r.ms(rf2)), 2)])
    w(table(["method", "arch", "Mpix/s 1T", "Mpix/s 2T", "÷ planar 1T", "÷ planar 2T", "÷ roofline 1T",
             "÷ roofline 2T"], rows, ["l", "l"] + ["r"] * 6))
    w("")

    # --- Pair ---
    w("## Centre → both eyes (`pair_`, `reproject_pair`, 1080p planar RGBA)")
    w("")
    w("Mpix/s counts both eyes' pixels. \"÷ two calls\" is the pair's time over that of two single-eye")
    w("calls for the same eyes (`pair_<method>/.../two_calls`: the left eye with the mirrored model, then")
    w("the right), in the same binary: below 1 the pair shares work between the eyes (each source row read")
    w("from memory once, one near pass). Measured on %s." % cpu.get("model", "unknown CPU"))
    w("")
    rows = []
    for method in METHODS:
        for arch in present:
            p1, p2 = name("pair_" + method, arch, FULL_HD, 1), name("pair_" + method, arch, FULL_HD, 2)
            c1, c2 = name("pair_" + method, arch, FULL_HD, 1, "/two_calls"), name("pair_" + method, arch, FULL_HD, 2, "/two_calls")
            rows.append([method, arch, fmt(r.ms(p1), 2), fmt(r.ms(c1), 2), fmt(ratio(r.ms(p1), r.ms(c1)), 2),
                         fmt(r.ms(p2), 2), fmt(r.ms(c2), 2), fmt(ratio(r.ms(p2), r.ms(c2)), 2),
                         fmt(ratio(r.ms(p2), r.ms(rf2) * 2 * 62.0 / 82.0) if r.ms(rf2) else None, 2)])
    w(table(["method", "arch", "pair ms 1T", "two calls ms 1T", "÷ two calls 1T", "pair ms 2T", "two calls ms 2T",
             "÷ two calls 2T", "pair ÷ its roofline 2T"], rows, ["l", "l"] + ["r"] * 7))
    w("")
    w("\"pair ÷ its roofline\": the pair's own bytes are 62 B/px of one eye (the source's 20 read once, two")
    w("eyes' 21 written), so its roofline is the one-eye roofline × 2 × 62 / 82.")
    w("")

    # --- Fixed near limit ---
    w("## A fixed near limit (`/near:fixed`, 1080p planar RGBA)")
    w("")
    w("`max_negative_parallax = |a| / 2`, as an engine sets it, instead of the frame's own nearest parallax.")
    w("`exact` then clips what is nearer (its SIMD sweep masks those pixels); the searching methods start")
    w("their rays there. \"÷ own\" is the time over the same method's with the frame's own limit. Measured")
    w("on %s." % cpu.get("model", "unknown CPU"))
    w("")
    rows = []
    for method in METHODS:
        for arch in present:
            f1, f2 = name(method, arch, FULL_HD, 1, "/near:fixed"), name(method, arch, FULL_HD, 2, "/near:fixed")
            rows.append([method, arch, fmt(r.ms(f1), 2), fmt(ratio(r.ms(f1), r.ms(name(method, arch, FULL_HD, 1))), 2),
                         fmt(r.ms(f2), 2), fmt(ratio(r.ms(f2), r.ms(name(method, arch, FULL_HD, 2))), 2)])
    w(table(["method", "arch", "ms 1T", "÷ own 1T", "ms 2T", "÷ own 2T"], rows, ["l", "l"] + ["r"] * 4))
    w("")

    # --- Engine-native formats ---
    w("## Engine-native pixel formats (`/<colour>+<depth>`, 1080p and 4K)")
    w("")
    w("The scene converted once, at set-up, to each engine format (`formats::` helpers; D24S8's stencil holds")
    w("the object id), colour output only, in the source's format: an engine's other eye. Each format's")
    w("roofline (`roofline/<W>x<H>/threads:<n>/<colour>+<depth>`) reads its colour and depth and writes its")
    w("colour, the bytes per pixel in each heading; \"÷ roofline\" is a case's time over its own format's")
    w("roofline at the same size and thread count. \"× float 2T\" is the time of the same method on the same")
    w("arch on `%s` (interleaved float RGBA + float depth) over this one: above 1 the format is" % FLOAT_FORMAT)
    w("faster. The cases run on AVX2 and the best arch only; rerun one format with e.g.")
    w("`--filter '/rgba8\\+unorm24_s8$'` (`+` is a regex operator). Measured on %s." % cpu.get("model", "unknown CPU"))
    w("")
    ran = False
    for size in FORMAT_SIZES:
        formats_ran = [f for f in FORMATS if any(n.endswith("/" + f[0]) and "/%s/" % size in n for n in r.rows)]
        ran = ran or bool(formats_ran)
        w("### %s" % size)
        w("")
        if not formats_ran:
            w("*This run has no `/<colour>+<depth>` results at %s (its binary predates them, or the filter left "
              "them out).*" % size)
            w("")
        for fmt_name, bpp in formats_ran:
            suffix = "/" + fmt_name
            rf1, rf2 = roofline(size, 1, suffix), roofline(size, 2, suffix)
            w("**%s** — %d B/px; roofline %s ms (%s GB/s) at 2 threads, %s ms (%s GB/s) at 1 thread" % (
                fmt_name, bpp, fmt(r.ms(rf2), 2), fmt(r.gbs(rf2), 1), fmt(r.ms(rf1), 2), fmt(r.gbs(rf1), 1)))
            w("")
            rows = []
            for method in METHODS:
                for arch in present:
                    n1, n2 = name(method, arch, size, 1, suffix), name(method, arch, size, 2, suffix)
                    if r.get(n1) is None and r.get(n2) is None:
                        continue
                    _, _, speedup = format_figures(method, arch, fmt_name, size)
                    row = [method, arch, fmt(r.ms(n2), 2), fmt(r.mpix(n2)), fmt(ratio(r.ms(n2), r.ms(rf2)), 2),
                           fmt(r.ms(n1), 2), fmt(ratio(r.ms(n1), r.ms(rf1)), 2), fmt(speedup, 3)]
                    if size == FULL_HD:
                        row.append("; ".join("%s **%s**" % tv for tv in format_targets.get((method, arch, fmt_name), []))
                                   or "–")
                    rows.append(row)
            header = ["method", "arch", "ms 2T", "Mpix/s 2T", "÷ roofline 2T", "ms 1T", "÷ roofline 1T", "× float 2T"]
            if size == FULL_HD:
                w(table(header + ["targets"], rows, ["l", "l"] + ["r"] * 6 + ["l"]))
            else:
                w(table(header, rows, ["l", "l"] + ["r"] * 6))
            w("")

    if ran:
        # Why the roofline targets are out of reach here: a measurement, with the command that
        # repeats it (instruction counts do not depend on the machine's load).
        w("**Where the time goes.** A format changes only the loads and stores, so it can remove memory")
        w("traffic, not work; the next section times the computation alone. Instructions per frame")
        w("(callgrind, AVX2 table, 1080p, colour output only, `valgrind --tool=callgrind")
        w("--toggle-collect='reproject::reproject(*'` on two calls of the bench case, e.g.")
        w("`--benchmark_filter='^single/avx2/1920x1080/threads:1/rgba8\\+unorm24_s8$' --benchmark_min_time=0.001`,")
        w("2026-11-26), before issue 23's kernels (5b03e03) and after (a404105): `single` on %s" % PACKED_FORMAT)
        w("105.2 M → 73.6 M (resolve 80.6 M → 58.8 M, decode 11.0 M → 7.9 M, search 13.0 M → 6.3 M);")
        w("`march16` on %s 192.4 M → 135.1 M (the march 93.3 M → 60.7 M); `single` on %s" % (PACKED_FORMAT, FLOAT_FORMAT))
        w("127.8 M → 100.3 M. What went: the resolve's frame-constant choices, masks and a thread-local")
        w("counter in every vector (now one loop per colour path for the plain vectors, the rest apart),")
        w("fields of the frame reloaded after every store (a float store may alias them), a zeroed column")
        w("plan per vector, an out-of-line call per vector for float RGBA, a shift and a mask per rgba8")
        w("channel (now one byte shuffle). What is left is the arithmetic the exact blend needs: per rgba8")
        w("channel two conversions to float, a subtraction, an FMA and a rounding conversion, then the pack.")
        packed_roof = r.ms(roofline(FULL_HD, 2, "/" + PACKED_FORMAT))
        per_pixel = "%.3f ns" % (packed_roof * 1e6 * 2 / (1920 * 1080)) if packed_roof else "a fraction of a ns"
        w("That is 17.8 instructions a pixel for `single` on AVX2, while the 2-thread %s roofline" % PACKED_FORMAT)
        w("leaves each core %s a pixel: this machine's 1080p working set sits in its L3, whose" % per_pixel)
        w("bandwidth is the roofline here, so ≤ 1.5× of it would need several times fewer instructions, not")
        w("fewer bytes. At 4K the frame no longer fits and the roofline is DRAM's: the same kernels come far")
        w("closer to it there (the 4K table above). `march16`'s march is the same on every format, which")
        w("bounds its speed-up over the float path below `single`'s.")
        w("")

    # --- Computation alone: a band of rows that stays in cache ---
    w("## Computation alone (band of %d rows in L2)" % BAND_ROWS)
    w("")
    band_pixels = 1920 * BAND_ROWS

    def ns_per_pixel(n):
        mpix = r.mpix(n)
        return 1e3 / mpix if mpix else None

    band_rows = []
    for fmt_name in BAND_FORMATS:
        for method in BAND_METHODS:
            for arch in present:
                for threads in THREADS:
                    band = name(method, arch, FULL_HD, threads, "/" + fmt_name + BAND)
                    if r.get(band) is None:
                        continue
                    b, f = ns_per_pixel(band), ns_per_pixel(name(method, arch, FULL_HD, threads, "/" + fmt_name))
                    roof = ns_per_pixel(roofline(FULL_HD, threads, "/" + fmt_name))
                    band_rows.append([fmt_name, method, arch, threads, fmt(b, 3), fmt(f, 3), fmt(roof, 3),
                                      fmt(ratio(b, roof), 2), fmt(ratio(b, f), 2),
                                      fmt(ns_per_pixel(roofline(FULL_HD, threads, "/" + fmt_name + BAND)), 3)])
    if not band_rows:
        w("*This run has no `%s` results (its binary predates them, or the filter left them out).*" % BAND)
        w("")
    else:
        w("`<method>/<arch>/1920x1080/threads:<n>/<colour>+<depth>%s` reprojects only rows %d..%d of the same" % (
            BAND, (1080 - BAND_ROWS) // 2, (1080 - BAND_ROWS) // 2 + BAND_ROWS - 1))
        w("1080p frame (sub-views of the same buffers: same width and strides, the band's height). After the")
        w("first call its bytes are in cache, so its time is the kernel's computation without the memory wall;")
        w("times are ns per target pixel (the band's %d pixels, the frame's 1920 × 1080), so they compare" % band_pixels)
        w("directly. \"roofline\" is the whole frame's own roofline at the same thread count (the memory")
        w("wall), \"band ÷ frame\" the share of the whole frame's time that the computation alone accounts")
        w("for, and \"band roofline\" the same copy over the band's rows (in cache: far below the roofline when")
        w("the band stays there).")
        l2 = [c["size"] for c in (context.get("caches") or []) if c.get("level") == 2]
        if l2:
            fits = []
            for fmt_name in BAND_FORMATS:
                band_bytes = dict(FORMATS)[fmt_name] * band_pixels
                where = ("in L2 at 1 and 2 threads" if band_bytes <= l2[0] else
                         "in L2 at 2 threads only (at 1 thread, in the next cache)" if band_bytes / 2 <= l2[0] else
                         "larger than L2 at 1 and 2 threads: in the next cache")
                fits.append("%s %.2f MB, %.2f MB a core at 2 threads: %s" % (
                    fmt_name, band_bytes / 1e6, band_bytes / 2e6, where))
            w("The band's bytes against this machine's L2 of %d KiB a core: %s." % (l2[0] // 1024, "; ".join(fits)))
        w("At 2 threads the band also pays the hand-off between the threads on each call, spread over %.0f×" %
          (1080 / BAND_ROWS))
        w("fewer pixels than a frame's, so its 2-thread figures overstate the computation.")
        w("")
        w(table(["format", "method", "arch", "threads", "band ns/px", "frame ns/px", "roofline ns/px", "band ÷ roofline",
                 "band ÷ frame", "band roofline ns/px"], band_rows, ["l", "l", "l"] + ["r"] * 7))
        w("")
        # Whether the 1.5× targets can be reached by memory-side changes: the computation alone, at
        # 2 threads, is at least half the band's 1-thread time (a perfect split over two cores, no
        # hand-off), and at most the band's 2-thread time.
        over, under = [], []
        for arch in format_archs:
            for method in ("single", "march16"):
                band1 = ns_per_pixel(name(method, arch, FULL_HD, 1, "/" + PACKED_FORMAT + BAND))
                band2 = ns_per_pixel(name(method, arch, FULL_HD, 2, "/" + PACKED_FORMAT + BAND))
                computation = min([v for v in (band1 / 2 if band1 else None, band2) if v is not None], default=None)
                value = ratio(computation, ns_per_pixel(roofline(FULL_HD, 2, "/" + PACKED_FORMAT)))
                if value is not None:
                    (over if value > 1.5 else under).append("%.2f× (`%s`, %s)" % (value, method, arch))
        if over or under:
            verdict = []
            if over:
                verdict.append("%s: above 1.5× before any memory traffic, so no memory-side change can bring %s "
                               "to the 1.5× target, only less computation" % (", ".join(over), "it" if len(over) == 1 else "them"))
            if under:
                verdict.append("%s: within 1.5×, so what separates %s from the target is memory traffic" % (
                    ", ".join(under), "it" if len(under) == 1 else "them"))
            w("On %s at 2 threads, the computation alone (half the band's 1-thread time, or its 2-thread time if "
              "less), as a multiple of the whole frame's roofline, is %s." % (PACKED_FORMAT, "; and ".join(verdict)))
            w("")

    # --- Observations: computed, so they stay true when the numbers change ---
    w("## Observations")
    w("")
    scan = []
    for arch in present:
        t8 = r.ms(name("scanline", arch, FULL_HD, 1, "/sep:8"))
        t128 = r.ms(name("scanline", arch, FULL_HD, 1, "/sep:128"))
        if t8 and t128:
            scan.append("%s %.2f× (%.1f → %.1f ms)" % (arch, t128 / t8, t8, t128))
    if scan:
        w("* `scanline` grows with separation, as an O(range) search must: time at a = 128 px over a = 8 px, "
          "1 thread: " + "; ".join(scan) + ".")
    fastest = []
    for threads in THREADS:
        best = [(r.mpix(name(m, best_arch(m, threads=threads), FULL_HD, threads)), m) for m in METHODS if best_arch(m, threads=threads)]
        best = [b for b in best if b[0] is not None]
        if best:
            top = max(best)
            fastest.append("%d thread%s: %s at %.1f Mpix/s = %s× roofline time" % (
                threads, "s" if threads > 1 else "", top[1], top[0],
                fmt(ratio(r.ms(name(top[1], best_arch(top[1], threads=threads), FULL_HD, threads)),
                          r.ms(roofline(FULL_HD, threads))), 2)))
    if fastest:
        w("* Fastest method at 1080p: " + "; ".join(fastest) + ".")
    bound = []  # (time ÷ roofline, method) at 1080p, 1 thread, best arch
    for method in METHODS:
        arch = best_arch(method)
        value = ratio(r.ms(name(method, arch, FULL_HD, 1)), r.ms(roofline(FULL_HD, 1))) if arch else None
        if value is not None:
            bound.append((value, method))
    if bound:
        listing = ", ".join("%s %.1f×" % (m, v) for v, m in bound)
        near = [m for v, m in bound if v <= 1.5]
        if not near:
            w("* No method is near memory speed: at 1080p, 1 thread, best arch, time ÷ roofline is %s. The same "
              "bytes stream %.1f–%.1f× faster than any kernel touches them, so the limit is instructions (search "
              "and resolve), not bandwidth." % (listing, min(bound)[0], max(bound)[0]))
        else:
            w("* Within 1.5× of memory speed at 1080p, 1 thread: %s (time ÷ roofline: %s)." % (", ".join(near), listing))
    grey_best = best_arch("march16", GREY_SIZE, 1, "/grey")
    if grey_best:
        g = r.mpix(name("march16", grey_best, GREY_SIZE, 1, "/grey"))
        f = r.mpix(name("march16", grey_best, FULL_HD, 1))
        if g and f:
            w("* march16 (%s) reaches %.1f Mpix/s on one grey plane in cache and %.1f Mpix/s on 1080p RGBA from "
              "memory: %.1f× apart, for 2.4× the bytes per pixel." % (grey_best, g, f, g / f))
    largest = max((c.get("size", 0) for c in (context.get("caches") or [])), default=0)
    if largest:
        fits = [s_ for s_ in SIZES if 41 * int(s_.split("x")[0]) * int(s_.split("x")[1]) <= largest]
        w("* The largest cache here is %d MiB; one eye's working set (41 B/px) is %s MB at 720p / 1080p / 4K, so %s. "
          "Where a frame stays in it, \"roofline\" is that cache's bandwidth rather than DRAM's; on a shared "
          "machine (a VM whose host's other tenants use the same cache) a large working set may not stay, which "
          "shows as a step in Mpix/s between sizes in the resolution table." % (
              largest // (1 << 20), " / ".join("%.0f" % (41e-6 * int(s_.split("x")[0]) * int(s_.split("x")[1])) for s_ in SIZES),
              ("the %s frames fit in it" % " and ".join(fits)) if fits else "no frame fits in it"))
    if r.errors:
        w("* Benchmarks that reported an error: " + "; ".join("`%s`: %s" % kv for kv in sorted(r.errors.items())))
    w("")

    # --- Why the kernels are written as they are: measurements kept by hand beside this script ---
    choices = pathlib.Path(__file__).resolve().parent / "design_measurements.md"
    if choices.exists():
        w("## Measured design choices")
        w("")
        for line in choices.read_text().splitlines():
            w(line)
        w("")

    # --- ARM: not timed here; the instruction mix from the object code instead ---
    w("## ARM")
    w("")
    w("ARM timings are **not yet measured**: no ARM hardware is at hand, and timings under `qemu-aarch64`")
    w("mean nothing (CI runs the aarch64 build's tests and a smoke run of this benchmark there, but")
    w("quotes no figure). What can be read without the hardware is the code itself, NEON's against")
    w("AVX2's: how many instructions each stage executes per pixel on the same call, counted under")
    w("QEMU (which counts correctly however slowly it runs), per pixel of the rows' vector bodies")
    w("(4 lanes on NEON, 8 on AVX2). The text below says how the tables were made.")
    w("")
    mix = pathlib.Path(__file__).resolve().parent / "arm_instruction_counts.md"
    if mix.exists():
        for line in mix.read_text().splitlines():
            w(line)
    else:
        w("(bench/arm_instruction_counts.md is missing: run bench/instruction_count.py, as its header says.)")
    w("")

    # --- Everything ---
    w("## All results")
    w("")
    w("<details><summary>Every benchmark of the run (median; cv = coefficient of variation of the time)</summary>")
    w("")
    rows = []
    for n in sorted(r.rows):
        rows.append(["`%s`" % n, fmt(r.ms(n), 3), fmt(r.mpix(n)), fmt(r.gbs(n), 2),
                     "–" if r.cv(n) is None else "%.1f %%" % (100 * r.cv(n))])
    w(table(["benchmark", "ms", "Mpix/s", "GB/s", "cv"], rows))
    w("")
    w("</details>")
    w("")

    # The video section is measured by bench/video_throughput.py, not by this run: carried over.
    if os.path.exists(doc_path):
        with open(doc_path, encoding="utf-8") as f:
            previous = f.read()
        start = previous.find("\n## Sequences and videos\n")
        if start >= 0:
            end = previous.find("\n## ", start + 1)
            out.append(previous[start + 1:end if end >= 0 else len(previous)].rstrip("\n") + "\n")
    os.makedirs(os.path.dirname(os.path.abspath(doc_path)), exist_ok=True)
    with open(doc_path, "w", encoding="utf-8") as f:
        f.write("\n".join(out))
    print("run_benchmarks.py: wrote %s (%d of %d targets met)" % (doc_path, met, counted))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", help="reproject_bench (default: build/bench, else the newest build*/bench)")
    parser.add_argument("--repetitions", type=int, default=3, help="repetitions per benchmark; medians are reported (default 3)")
    parser.add_argument("--filter", default="", help="--benchmark_filter regex (default: every benchmark)")
    parser.add_argument("--min-time", type=float, default=0.2,
                        help="--benchmark_min_time per repetition, seconds (default 0.2; a case slower than this "
                             "runs one iteration per repetition, which bounds the 4K scalar ones)")
    parser.add_argument("--no-interleave", dest="interleave", action="store_false",
                        help="run each benchmark's repetitions back to back instead of randomly interleaved")
    parser.add_argument("--wait-idle", type=float, metavar="LOAD",
                        help="first wait until the 1-minute load average is below LOAD (at most --wait-max)")
    parser.add_argument("--wait-max", type=float, default=1800, metavar="SECONDS",
                        help="longest wait for --wait-idle (default 1800)")
    parser.add_argument("--out", help="where to keep the JSON (default: reproject_bench.json next to the binary)")
    parser.add_argument("--doc", default=os.path.join(REPO, "docs", "PERFORMANCE.md"), help="the page to write")
    parser.add_argument("--from-json", help="do not run: regenerate the page from a JSON this script kept")
    args = parser.parse_args()
    if args.repetitions < 1:
        parser.error("--repetitions must be >= 1")

    if args.from_json:
        with open(args.from_json, encoding="utf-8") as f:
            data = json.load(f)
        json_path = os.path.abspath(args.from_json)
    else:
        data, json_path = run(args)
    write_page(data, json_path, args.doc)


if __name__ == "__main__":
    main()
