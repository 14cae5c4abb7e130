#!/usr/bin/env python3
"""Every reproject method on your own colour + disparity pair: PSNR against the true other view and
time per method, and a red/cyan anaglyph of the left view with the synthesised right one.

    python3 examples/compare_methods.py                                    # the teddy pair of tests/data
    python3 examples/compare_methods.py --left im2.png --disparity disp2.png --scale 0.25 --right im6.png

The disparity image holds disparity * (1 / scale) in pixels (Middlebury: 4 x disparity, 0 = unknown);
unknown pixels take the farther of their nearest known row neighbours before warping, as the CLI's
--unknown-depth does. PSNR (peak 255) is scored where `exact` finds a hit, the same pixels for every
method, against --right when it is given. It needs the package installed (README.md, Python), or
PYTHONPATH=build/python after a CMake build; mypy checks it against the package's types.
"""
import argparse
import pathlib
import time

import numpy as np
import numpy.typing as npt
from PIL import Image

import reproject

TEDDY = pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "teddy"


def fill_unknown(disparity: npt.NDArray[np.float32]) -> npt.NDArray[np.float32]:
    """Each unknown (0) disparity takes the smaller (farther) of its nearest known row neighbours."""
    known = disparity != 0
    width = disparity.shape[1]
    columns = np.arange(width)
    before = np.maximum.accumulate(np.where(known, columns, -1), axis=1)
    after = np.minimum.accumulate(np.where(known, columns, width)[:, ::-1], axis=1)[:, ::-1]
    rows = np.arange(disparity.shape[0])[:, None]
    left = np.where(before >= 0, disparity[rows, before.clip(0, width - 1)], np.inf)
    right = np.where(after < width, disparity[rows, after.clip(0, width - 1)], np.inf)
    nearest = np.minimum(left, right)
    return np.where(known, disparity, np.where(np.isinf(nearest), 0, nearest)).astype(np.float32)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--left", default=TEDDY / "im2.png", help="left colour image")
    parser.add_argument("--disparity", default=TEDDY / "disp2.png", help="the left view's disparity image")
    parser.add_argument("--scale", type=float, default=0.25, help="disparity in pixels per stored unit")
    parser.add_argument("--right", default=TEDDY / "im6.png", help="the true right view (optional)")
    parser.add_argument("--anaglyph", default="anaglyph.png", help="where to write the anaglyph")
    parser.add_argument("--repeats", type=int, default=5, help="runs per method; the median is printed")
    args = parser.parse_args()

    left = np.asarray(Image.open(args.left).convert("RGB"), dtype=np.float32)
    # Planes (3, H, W): the layout the library reads in place, so the timing is the kernels'.
    planes = np.ascontiguousarray(np.moveaxis(left, -1, 0))
    disparity = fill_unknown(np.asarray(Image.open(args.disparity), dtype=np.float32) * np.float32(args.scale))
    truth = np.asarray(Image.open(args.right).convert("RGB"), dtype=np.float32) if args.right else None

    results: dict[reproject.Method, tuple[reproject.Result, float]] = {}
    for method in reproject.methods:
        result = reproject.warp(planes, disparity, encoding="disparity", direction="left-to-right", method=method)
        times = []
        for _ in range(args.repeats):  # out=result: the timed runs allocate nothing
            start = time.perf_counter()
            reproject.warp(planes, disparity, encoding="disparity", direction="left-to-right", method=method,
                           out=result)
            times.append(time.perf_counter() - start)
        results[method] = (result, float(np.median(times)))

    scored = results["exact"][0].status == 0
    print(f"{left.shape[1]}x{left.shape[0]}, arch {reproject.selected_arch()}, scored {scored.mean():.1%} of the pixels")
    for method, (result, seconds) in results.items():
        psnr = ""
        if truth is not None:
            error = np.moveaxis(result.color, 0, -1)[scored] - truth[scored]
            psnr = f"PSNR {10 * np.log10(255.0 ** 2 / np.mean(error.astype(np.float64) ** 2)):6.2f} dB  "
        print(f"{method:<9} {psnr}{seconds * 1e3:7.2f} ms  holes {np.mean(result.status == 1):.2%}")

    # Red from the left eye, green and blue from the synthesised right eye.
    right = np.moveaxis(results["exact"][0].color, 0, -1)
    anaglyph = np.concatenate([left[:, :, :1], right[:, :, 1:]], axis=2)
    Image.fromarray(np.clip(anaglyph + 0.5, 0, 255).astype(np.uint8)).save(args.anaglyph)
    print(f"anaglyph: {args.anaglyph}")


if __name__ == "__main__":
    main()
