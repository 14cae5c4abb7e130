#!/usr/bin/env python3
"""Warp the held-out real stereo pairs (tests/data/middlebury2001) with the command-line tool and
print one line per output: pair, method, arch, output, and the SHA-256 of its decoded pixels.

Two builds (say x86 with --arch avx2 and aarch64 under qemu with --arch neon) are bit-identical
when their listings, arch names aside, are equal; ci compares them with --compare.

  warp_outputs.py --cli 'qemu-aarch64 build-arm/tools/reproject' --arch neon --out listing.txt
  warp_outputs.py --compare a.txt b.txt
"""
import argparse
import hashlib
import pathlib
import shlex
import subprocess
import sys
import tempfile

from PIL import Image

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "middlebury2001"
# pair: left colour, its disparity (PGM), disparity scale.
PAIRS = {"tsukuba": ("im3.png", "disp3.pgm", 1 / 16), "venus": ("im2.png", "disp2.pgm", 1 / 8)}
METHODS = ["scanline", "march16", "single", "secant", "exact"]


def pixels_digest(path: pathlib.Path) -> str:
    """SHA-256 of the pixels, not of the file: a PNG's compressed bytes may differ between builds
    of zlib; a PFM is its header and raw floats."""
    if path.suffix == ".pfm":
        return hashlib.sha256(path.read_bytes()).hexdigest()
    image = Image.open(path)
    return hashlib.sha256(f"{image.mode} {image.size}".encode() + image.tobytes()).hexdigest()


def run(cli, arch, out):
    lines = []
    with tempfile.TemporaryDirectory() as work:
        work = pathlib.Path(work)
        for pair, (color, disparity, scale) in PAIRS.items():
            # The CLI reads PNG, not PGM: the same 8-bit values, losslessly.
            depth = work / f"{pair}_disparity.png"
            Image.open(DATA / pair / disparity).save(depth)
            for method in METHODS:
                for color_path in ("native", "float"):
                    prefix = work / f"{pair}_{method}_{color_path}"
                    outputs = {"colour": prefix.with_suffix(".png" if color_path == "native" else ".pfm"),
                               "depth": pathlib.Path(f"{prefix}_depth.pfm"),
                               "status": pathlib.Path(f"{prefix}_status.png"),
                               "source_x": pathlib.Path(f"{prefix}_x.pfm")}
                    command = shlex.split(cli) + [
                        "warp", "--color", str(DATA / pair / color), "--depth", str(depth), "--disparity",
                        "--depth-scale", repr(scale), "--unknown-depth", "0", "--method", method, "--arch", arch,
                        "--out", str(outputs["colour"]), "--out-depth", str(outputs["depth"]),
                        "--status", str(outputs["status"]), "--source-x", str(outputs["source_x"])]
                    if color_path == "float":
                        command.append("--float-color")
                    result = subprocess.run(command, capture_output=True, text=True)
                    if result.returncode != 0:
                        sys.exit(f"{' '.join(command)} failed ({result.returncode}):\n{result.stderr}")
                    for name, path in outputs.items():
                        lines.append(f"{pair} {method} {color_path} {name} {pixels_digest(path)}")
    pathlib.Path(out).write_text("\n".join(lines) + "\n")
    print(f"{out}: {len(lines)} outputs of {len(PAIRS)} pairs x {len(METHODS)} methods x 2 colour paths, --arch {arch}")


def compare(a, b):
    left = pathlib.Path(a).read_text().splitlines()
    right = pathlib.Path(b).read_text().splitlines()
    if len(left) != len(right) or not left:
        sys.exit(f"{a} has {len(left)} outputs, {b} {len(right)}")
    differ = [f"  {x}\n  {y}" for x, y in zip(left, right) if x != y]
    if differ:
        sys.exit(f"{len(differ)} of {len(left)} outputs differ between {a} and {b}:\n" + "\n".join(differ[:10]))
    print(f"{a} = {b}: all {len(left)} outputs identical")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", help="how to run the tool, e.g. 'build/tools/reproject'")
    parser.add_argument("--arch", help="the instruction set to force (--arch)")
    parser.add_argument("--out", help="where to write the listing")
    parser.add_argument("--compare", nargs=2, metavar="LISTING")
    options = parser.parse_args()
    if options.compare:
        compare(*options.compare)
    else:
        run(options.cli, options.arch, options.out)
