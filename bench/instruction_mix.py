#!/usr/bin/env python3
"""The instruction mix of the SIMD inner loops, read from the kernels' object code: for each named
kernel, its per-vector loop (the outermost loop of the function: one vector of pixels per turn,
every branch of its body counted once) and, where it has loops inside that one, its innermost loop,
with the instruction count and how many of those are vector instructions, per pixel of the loop's
vector (4 lanes on NEON, 8 on AVX2). Static counts: a loop body with several paths (the resolve's
column-fetch modes) counts all of them, so they compare families, not times. Used where no hardware
runs the code (ARM here): docs/PERFORMANCE.md "ARM".

  bench/instruction_mix.py --neon build-arm/CMakeFiles/reproject_simd_neon.dir/kernels/arch_neon.cpp.o \\
      --avx2 build/CMakeFiles/reproject_simd_avx2.dir/kernels/arch_avx2.cpp.o
"""
import argparse
import re
import subprocess

# (label, a piece of the function's name): the stages an rgba8 + D24S8 frame runs through.
KERNELS = (
    ("decode (every depth format)", "::simd_decode<"),
    ("single search", "::simd_single<"),
    ("march16 search", "::simd_march16_row<"),
    ("march16 search", "::simd_march16<"),
    ("resolve, rgba8 colour only", "::resolve_hits<(reproject::detail::(anonymous namespace)::ColourPath)3, false,"),
    ("resolve, float planes + depth", "::resolve_hits<(reproject::detail::(anonymous namespace)::ColourPath)0, true,"),
)


def functions(objdump, path):
    listing = subprocess.run([objdump, "-d", "--no-show-raw-insn", "-C", path], capture_output=True, text=True,
                             check=True).stdout
    current, body = None, []
    for line in listing.splitlines():
        header = re.match(r"^([0-9a-f]+) <(.*)>:$", line)
        if header:
            if current:
                yield current, body
            current, body = header.group(2), []
            continue
        m = re.match(r"^\s+([0-9a-f]+):\t(\S+)\s*(.*)$", line)
        if m and current:
            body.append((int(m.group(1), 16), m.group(2), m.group(3)))
    if current:
        yield current, body


def is_vector(mnemonic, operands, neon):
    if neon:
        return bool(re.search(r"\bv\d+\.|\bq\d+\b", operands))
    return bool(re.search(r"%[xyz]mm", operands)) and not re.match(r"v?(cvtt?ss2si|movss|cvtsi2ss)$", mnemonic)


def loops(body):
    """(start, end) of every backward branch's range, innermost (shortest) first."""
    found = []
    for address, mnemonic, operands in body:
        if mnemonic.startswith(("b", "j", "cb", "tb")) and mnemonic not in ("bl", "blr", "br", "bic", "bif", "bit", "bsl"):
            target = re.match(r"([0-9a-f]+)\s<", operands)
            if target and int(target.group(1), 16) <= address and int(target.group(1), 16) >= body[0][0]:
                found.append((int(target.group(1), 16), address))
    return sorted(set(found), key=lambda r: r[1] - r[0])


def contains(outer, inner):
    return outer != inner and outer[0] <= inner[0] and inner[1] <= outer[1]


def mix(objdump, path, neon, lanes):
    """(label, loop kind, instructions, vector instructions) of each named kernel's loops: its
    per-vector loop and innermost loop when the function has one outer loop, else the range over
    its outer loops (one per variant: a depth format and decode shape, say)."""
    rows = []
    for name, body in functions(objdump, path):
        label = next((label for label, piece in KERNELS if piece in name), None)
        if label is None or "Fused" not in name:
            continue
        found = loops(body)
        if "march16" in label:
            label += " (s > 0)" if ", true>" in name else " (s < 0)" if ", false>" in name else ""

        def size(loop):
            inside = [(m, o) for a, m, o in body if loop[0] <= a <= loop[1]]
            return len(inside), sum(is_vector(m, o, neon) for m, o in inside)

        outer = [l for l in found if not any(contains(o, l) for o in found)]
        if len(outer) == 1:
            rows.append((label, "per vector") + size(outer[0]))
            leaves = [l for l in found if not any(contains(l, i) for i in found)]
            if leaves and leaves[0] != outer[0]:
                rows.append((label, "innermost") + size(leaves[0]))
        elif outer:
            sizes = sorted(size(l) for l in outer)
            rows.append((label, "%d loops, one per variant: fewest, most" % len(outer), sizes[0], sizes[-1]))
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--neon", required=True)
    parser.add_argument("--avx2", required=True)
    parser.add_argument("--neon-objdump", default="aarch64-linux-gnu-objdump")
    parser.add_argument("--objdump", default="objdump")
    options = parser.parse_args()
    rows = {}
    for family, objdump, path, neon, lanes in (("NEON", options.neon_objdump, options.neon, True, 4),
                                               ("AVX2", options.objdump, options.avx2, False, 8)):
        for label, kind, *counts in mix(objdump, path, neon, lanes):
            rows.setdefault((label, kind), {})[family] = (counts, lanes)

    def cell(counts, lanes):
        """instructions (vector) per loop turn and per pixel; a (fewest, most) pair for variants."""
        if isinstance(counts[0], tuple):
            return "%d–%d (%d–%d)" % (counts[0][0], counts[1][0], counts[0][1], counts[1][1]), \
                   "%.2f–%.2f (%.2f–%.2f)" % (counts[0][0] / lanes, counts[1][0] / lanes, counts[0][1] / lanes,
                                             counts[1][1] / lanes)
        return "%d (%d)" % tuple(counts), "%.2f (%.2f)" % (counts[0] / lanes, counts[1] / lanes)

    print("| kernel | loop | NEON: instructions (vector) | per pixel, 4 lanes | AVX2: instructions (vector) | per pixel, 8 lanes |")
    print("|:--|:--|--:|--:|--:|--:|")
    for (label, kind), families in rows.items():
        cells = []
        for family in ("NEON", "AVX2"):
            cells += list(cell(*families[family])) if family in families else ["–", "–"]
        print("| %s | %s | %s |" % (label, kind, " | ".join(cells)))
