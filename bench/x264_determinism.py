#!/usr/bin/env python3
"""Whether reproject.video's x264 output is the same from run to run, under x264's defaults and
under the setting convert uses (cpu-independent=1), and what that setting costs in speed
(docs/CLI.md "convert").

    PYTHONPATH=build/python python3 bench/x264_determinism.py             # bitstreams
    PYTHONPATH=build/python python3 bench/x264_determinism.py --speed 11  # frames/s, alternating

Bitstreams: the tests' clip (tests/python/media.py: a moving texture, x264 colour, millimetre
depth; 60 frames) at several widths, converted to full side by side with x264 in segments of 6
frames, once per x264 setting and per MALLOC_PERTURB_ byte, each run in a fresh process (glibc
fills the memory it frees with that byte, so an encoder that reads memory it never wrote gives an
output that follows the byte). Prints how many different outputs each setting gave, and whether
cpu-independent=1 gives x264's C reference (asm=0) whatever assembly runs (here, and capped at
SSE4.2 as an older CPU would be).
Speed: x264 alone on 24 frames of 3840x1080 (side by side of 1080p), x264's defaults against
cpu-independent=1, the two alternating round by round; medians, and the median per-round ratio.
"""
import argparse
import hashlib
import os
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "python"))

SETTINGS = {"x264 defaults": "", "asm capped at AVX2": "asm=SSE2Fast,AVX2", "asm=0": "asm=0",
            "cpu-independent=1": "cpu-independent=1", "cpu-indep., SSE4.2": "cpu-independent=1:asm=SSE4.2"}
GARBAGE = (0, 1, 85, 170)


def convert_with(folder, params):
    """Child process: convert the clip in `folder` with x264-params `params` (+ frame-packing) and
    print the output's hash."""
    import reproject.video as video
    settings = video._video_settings

    def with_params(spec, *args):
        settings(spec, *args)
        spec.options["x264-params"] = ":".join(p for p in ("frame-packing=3", params) if p)
    video._video_settings = with_params
    out = os.path.join(folder, f"out{os.getpid()}.mkv")
    video.convert(os.path.join(folder, "colour.mp4"), os.path.join(folder, "depth.mkv"), out, codec="libx264",
                  segment_frames=6, threads=1, encoding="linear", depth_scale=0.001, convergence=4.0)
    with open(out, "rb") as f:
        print(hashlib.sha256(f.read()).hexdigest())
    os.remove(out)


def bitstreams():
    import media
    print("different outputs over MALLOC_PERTURB_ = " + ", ".join(map(str, GARBAGE)) + " (1: the same every run)")
    print(f"{'output width':>12} {'MBs':>4}  " + "  ".join(f"{name:>18}" for name in SETTINGS) +
          "  the last three give one output")
    for width in (96, 120, 128, 192):
        with tempfile.TemporaryDirectory(prefix="reproject-x264-") as folder:
            media.write_video(os.path.join(folder, "colour.mp4"), [media.texture(width, 64, k) for k in range(60)],
                              "yuv420p", codec="libx264")
            media.write_video(os.path.join(folder, "depth.mkv"), [media.depth_codes(width, 64, k) for k in range(60)],
                              "gray16le", source_format="gray16le")
            outputs = []
            for params in SETTINGS.values():
                outputs.append(set())
                for garbage in GARBAGE:
                    done = subprocess.run([sys.executable, __file__, "--child", folder, params], capture_output=True,
                                          text=True, check=True, env=dict(os.environ, MALLOC_PERTURB_=str(garbage)))
                    outputs[-1].add(done.stdout.strip())
        same = "yes" if len(set.union(*outputs[2:])) == 1 else "no"
        print(f"{2 * width:>12} {2 * width // 16:>4}  " + "  ".join(f"{len(o):>18}" for o in outputs) + f"  {same:>30}")


def speed(rounds):
    import av
    import numpy as np
    import media
    pictures = []
    for k in range(24):
        eye = media.texture(1920, 1080, k)
        pictures.append(av.VideoFrame.from_ndarray(np.concatenate([eye, np.roll(eye, 7, axis=1)], axis=1),
                                                   format="rgb24").reformat(format="yuv420p"))

    def encode(params):
        out = av.open(os.devnull, "w", format="nut")
        stream = out.add_stream("libx264", rate=24)
        stream.width, stream.height, stream.pix_fmt = 3840, 1080, "yuv420p"
        stream.options = {"crf": "18", "x264-params": ":".join(p for p in ("frame-packing=3", params) if p)}
        start = time.perf_counter()
        for i, frame in enumerate(pictures):
            frame.pts = i
            for _ in stream.encode(frame):
                pass
        for _ in stream.encode(None):
            pass
        out.close()
        return len(pictures) / (time.perf_counter() - start)
    defaults, independent = [], []
    for r in range(rounds):
        if r % 2:
            independent.append(encode("cpu-independent=1"))
            defaults.append(encode(""))
        else:
            defaults.append(encode(""))
            independent.append(encode("cpu-independent=1"))
    print(f"x264 defaults:     median {statistics.median(defaults):.2f} frames/s  "
          f"(runs {', '.join(f'{x:.2f}' for x in defaults)})")
    print(f"cpu-independent=1: median {statistics.median(independent):.2f} frames/s  "
          f"(runs {', '.join(f'{x:.2f}' for x in independent)})")
    print(f"per-round ratio cpu-independent / defaults: median "
          f"{statistics.median(b / a for a, b in zip(defaults, independent)):.3f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speed", type=int, metavar="ROUNDS", help="time x264's defaults against cpu-independent=1")
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        convert_with(*args.child)
    elif args.speed:
        speed(args.speed)
    else:
        bitstreams()


if __name__ == "__main__":
    main()
