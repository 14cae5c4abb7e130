#!/usr/bin/env python3
"""Instructions executed per pixel by each stage of reprojection calls, counted under QEMU's
user-mode emulation, so that NEON (aarch64) and AVX2 (x86-64) can be compared on the same calls
where no ARM hardware is at hand. Counts only: emulated timings mean nothing.

QEMU logs every translated block's instructions once (-d in_asm) and every block it executes
(-d exec, with nochain so that chained blocks are logged too); the executed blocks' instructions,
summed per function, are the dynamic instruction counts, and the vector ones are those with a
vector register operand. The calls are reproject_golden's, picked with --only (bench/golden_outputs.cpp):

  bench/instruction_count.py --qemu qemu-aarch64 --binary build-arm/bench/reproject_golden --arch neon \\
      --only 'room/333x40/rgba8\\+unorm24_s8/single/neon/fill:background,edge:clamp,dir:right-to-left,out:colour/' \\
      --width 333 --height 40 --lanes 4
  bench/instruction_count.py --qemu 'qemu-x86_64 -cpu max' --binary build/bench/reproject_golden --arch avx2 ...

QEMU 7.2 emulates AVX2, FMA and F16C (not AVX-512). Counts are per pixel of the rows' vector
bodies (--width and --height of the frame, --lanes of the set: NEON 4, AVX2 8); the scalar tails
(the references, namespace host:: on x86) are listed apart. A run takes minutes: QEMU logs every
block the whole program executes, ray casting of the frame included.
"""
import argparse
import collections
import os
import re
import shlex
import subprocess
import tempfile

# Stages, by a piece of the (demangled) function name; the first match wins.
STAGES = (
    ("decode", ("simd_decode<", "decode_parallax_columns<", "simd_nearest_key<", "nearest_key_in_columns<")),
    ("search", ("simd_single<", "simd_march16", "march_range<", "search_row_single<", "search_row_march16<", "simd_exact<",
                "search_row_exact<", "simd_scanline<", "simd_secant<", "search_row_")),
    # (`single` on a SIMD table: its search runs inside the resolve's hit loop, simd_single_and_resolve.)
    ("resolve", ("resolve_hits<", "resolve_vector<", "simd_resolve<", "simd_single_and_resolve<", "resolve_pixels<")),
)


def demangle(names):
    if not names:
        return {}
    out = subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True, check=True).stdout
    return dict(zip(names, out.splitlines()))


def count(log_path, aarch64):
    """{symbol: (instructions, vector instructions)} executed, from a QEMU in_asm + exec log."""
    vector_operand = re.compile(r"\bv\d+\.|\bq\d+\b" if aarch64 else r"[xyz]mm\d")
    blocks = {}  # pc -> (instructions, vector instructions)
    executed = collections.Counter()  # (pc, symbol) -> times
    pc, instructions, vectors = None, 0, 0
    with open(log_path, errors="replace") as log:
        for line in log:
            if line.startswith("Trace "):
                m = re.match(r"Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/[0-9a-f]+\] ?(.*)$", line.rstrip("\n"))
                if m:
                    executed[(int(m.group(1), 16), m.group(2))] += 1
                continue
            if line.startswith("IN:"):
                pc, instructions, vectors = None, 0, 0
                continue
            m = re.match(r"^0x([0-9a-f]+):\s+(.*)$", line)
            if m:
                if pc is None:
                    pc = int(m.group(1), 16)
                instructions += 1
                vectors += bool(vector_operand.search(m.group(2)))
                blocks[pc] = (instructions, vectors)
    per_symbol = collections.defaultdict(lambda: [0, 0])
    for (pc, symbol), times in executed.items():
        if pc in blocks:
            per_symbol[symbol][0] += times * blocks[pc][0]
            per_symbol[symbol][1] += times * blocks[pc][1]
    return per_symbol


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--qemu", required=True, help="the emulator and its options, e.g. 'qemu-x86_64 -cpu max'")
    parser.add_argument("--binary", required=True, help="reproject_golden of that processor")
    parser.add_argument("--arch", required=True)
    parser.add_argument("--only", required=True, help="reproject_golden --only REGEX")
    parser.add_argument("--width", type=int, required=True, help="the calls' frame width (no guard band)")
    parser.add_argument("--height", type=int, required=True)
    parser.add_argument("--lanes", type=int, required=True, help="float lanes of the instruction set (NEON 4, AVX2 8)")
    options = parser.parse_args()
    aarch64 = "aarch64" in options.qemu
    with tempfile.TemporaryDirectory() as work:
        log = os.path.join(work, "qemu.log")
        command = shlex.split(options.qemu) + ["-d", "in_asm,exec,nochain", "-D", log, options.binary, "--arch",
                                               options.arch, "--only", options.only]
        run = subprocess.run(command, capture_output=True, text=True)
        calls = [l for l in run.stdout.splitlines() if not l.startswith("total")]
        if run.returncode != 0 or not calls:
            raise SystemExit("reproject_golden ran no call (%d): %s" % (run.returncode, run.stderr.strip()))
        per_symbol = count(log, aarch64)
    pixels = len(calls) * options.height * (options.width // options.lanes * options.lanes)
    names = demangle(list(per_symbol))
    stages = collections.defaultdict(lambda: [0, 0])
    functions = collections.defaultdict(lambda: [0, 0])
    for symbol, (instructions, vectors) in per_symbol.items():
        name = names.get(symbol, symbol)
        stage = next((s for s, pieces in STAGES if any(p in name for p in pieces)), None)
        if stage is None:
            continue
        short = re.sub(r"reproject::detail::|\(anonymous namespace\)::|xsimd::|, reproject::detail::Fused", "", name)
        short = re.sub(r"\(ColorPath\)(\d)", r"path \1", short)
        short = re.sub(r"\(.*", "", short)
        if re.search(r"\bhost::|search_row_|decode_parallax_columns|nearest_key_in_columns|resolve_pixels", short):
            stage = "scalar tails"
        for total in (stages[stage], functions[(stage, short)]):
            total[0] += instructions
            total[1] += vectors
    print("%d call(s): %s" % (len(calls), "; ".join(c.rsplit(" ", 1)[0] for c in calls)))
    print("| stage | function | instructions per pixel | of which vector |")
    print("|:--|:--|--:|--:|")
    for stage in [s for s, _ in STAGES] + ["scalar tails"]:
        for (s, short), (instructions, vectors) in sorted(functions.items()):
            if s == stage:
                print("| %s | `%s` | %.2f | %.2f |" % (stage, short, instructions / pixels, vectors / pixels))
        instructions, vectors = stages[stage]
        if stage != "scalar tails":
            print("| **%s** | all | **%.2f** | **%.2f** |" % (stage, instructions / pixels, vectors / pixels))


if __name__ == "__main__":
    main()
