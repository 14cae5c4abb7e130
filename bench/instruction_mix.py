#!/usr/bin/env python3
"""The instruction mix of the SIMD inner loops, read from the kernels' object code: for each named
kernel, every loop (a backward branch and the code it jumps back over) with its instruction count
and how many of those are vector instructions, per pixel of the loop's vector (4 lanes on NEON,
8 on AVX2). Used where no hardware runs the code (ARM here): docs/PERFORMANCE.md "ARM".

  bench/instruction_mix.py --neon build-arm/CMakeFiles/reproject_simd_neon.dir/kernels/arch_neon.cpp.o \\
      --avx2 build/CMakeFiles/reproject_simd_avx2.dir/kernels/arch_avx2.cpp.o
"""
import argparse
import re
import subprocess

KERNELS = ("simd_single", "simd_march16")  # the searches of `single` and `march16`


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
        kernel = next((k for k in KERNELS if f"::{k}<" in name or f"::{k}_row<" in name), None)
        if kernel is None or ("Fused" not in name):
            continue
        for start, end in loops(body):
            inside = [(m, o) for a, m, o in body if start <= a <= end]
            vector = sum(is_vector(m, o, neon) for m, o in inside)
            rows.append((kernel, name, start, len(inside), vector, lanes))
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--neon", required=True)
    parser.add_argument("--avx2", required=True)
    parser.add_argument("--neon-objdump", default="aarch64-linux-gnu-objdump")
    parser.add_argument("--objdump", default="objdump")
    options = parser.parse_args()
    print("| kernel | family | loop at | instructions | vector | per pixel (vector) |")
    print("|:--|:--|--:|--:|--:|--:|")
    for family, objdump, path, neon, lanes in (("NEON, 4 lanes", options.neon_objdump, options.neon, True, 4),
                                               ("AVX2, 8 lanes", options.objdump, options.avx2, False, 8)):
        for kernel, name, start, count, vector, lanes in mix(objdump, path, neon, lanes):
            variant = " (s > 0)" if ", true>" in name else (" (s < 0)" if ", false>" in name else "")
            print(f"| {kernel}{variant} | {family} | 0x{start:x} | {count} | {vector} | "
                  f"{count / lanes:.2f} ({vector / lanes:.2f}) |")
