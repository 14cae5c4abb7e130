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


def mix(objdump, path, neon, lanes):
    rows = []
    for name, body in functions(objdump, path):
        label = next((label for label, piece in KERNELS if piece in name), None)
        if label is None or "Fused" not in name:
            continue
        found = loops(body)
        if not found:
            continue
        picked = [("per vector", found[-1])] + ([("innermost", found[0])] if len(found) > 1 else [])
        for kind, (start, end) in picked:
            inside = [(m, o) for a, m, o in body if start <= a <= end]
            vector = sum(is_vector(m, o, neon) for m, o in inside)
            variant = " (s > 0)" if ", true>" in name and "march16" in label else (
                " (s < 0)" if ", false>" in name and "march16" in label else "")
            rows.append((label + variant, kind, start, len(inside), vector, lanes))
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
        for label, kind, start, count, vector, lanes in mix(objdump, path, neon, lanes):
            rows.setdefault((label, kind), {})[family] = (count, vector, lanes)
    print("| kernel | loop | NEON (4 lanes): instructions, vector | per pixel | AVX2 (8 lanes): instructions, vector | per pixel |")
    print("|:--|:--|--:|--:|--:|--:|")
    for (label, kind), families in rows.items():
        cells = []
        for family in ("NEON", "AVX2"):
            if family in families:
                count, vector, lanes = families[family]
                cells += ["%d, %d" % (count, vector), "%.2f (%.2f vector)" % (count / lanes, vector / lanes)]
            else:
                cells += ["–", "–"]
        print("| %s | %s | %s |" % (label, kind, " | ".join(cells)))
