#!/usr/bin/env python3
"""Frames per second of reproject.video's stages on a 1080p clip, and end to end in one process
against a local Dask cluster of two (docs/PERFORMANCE.md "Sequences and videos").

    PYTHONPATH=build/python python3 bench/video_throughput.py --frames 96 --repeats 3

The clip: a textured plane and a moving box (tests/python/media.py), colour as x264 yuv420p,
depth as FFV1 16-bit grey millimetres. Each stage is timed on its own, over the whole clip, in one
thread of Python (the library's own threads: --threads): decoding (colour and depth to the
working arrays), reprojection (warp_pair), packing (full side by side) and encoding (x264,
yuv420p, CRF 18). End to end: reproject.video.convert to a side-by-side x264 video. Each figure
is the median of --repeats runs; the machine is shared, so the spread is printed too.
"""
import argparse
import os
import statistics
import sys
import tempfile
import time


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "python"))
import media  # noqa: E402
import reproject  # noqa: E402
import reproject.video as video  # noqa: E402
from reproject import _media  # noqa: E402

CAMERA = dict(encoding="linear", depth_scale=0.001, convergence=4.0)


def timed(function, repeats):
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        seconds.append(time.perf_counter() - start)
    return seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=96)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args()
    width, height, count = 1920, 1080, args.frames
    folder = tempfile.mkdtemp(prefix="reproject-throughput-")
    color_path, depth_path = os.path.join(folder, "colour.mp4"), os.path.join(folder, "depth.mkv")
    media.write_video(color_path, [media.texture(width, height, k) for k in range(count)], "yuv420p",
                      codec="libx264", options={"crf": "18"})
    media.write_video(depth_path, [media.depth_codes(width, height, k) for k in range(count)], "gray16le",
                      source_format="gray16le")
    job = video._plan(color_path, depth_path, os.path.join(folder, "sbs.mp4"), "sbsl", False, None, None, None, None,
                      video._resolve_camera("linear", None, None, None, 4.0, None, None, False, None, None, False,
                                            None), 0.001, None, 0, dict(method="exact"), None, args.threads)
    decoder, model = video._camera(job, width)
    arrays = []

    def decode():
        arrays.clear()
        for i, (c, d) in enumerate(zip(job.color.frames(0, count), job.depth.frames(0, count))):
            color = _media.color_array(c, job.working, job.colorspace)
            depth = video._depth_values(job, d, i, decoder)
            if i < 8:
                arrays.append((color, depth))

    def reproject_all():
        previous = None
        for i in range(count):
            color, depth = arrays[i % len(arrays)]
            previous = reproject.warp_pair(color, depth, decoder=decoder, model=model, threads=args.threads,
                                           out_left=previous.left if previous else None,
                                           out_right=previous.right if previous else None)
    decode()
    pair = reproject.warp_pair(arrays[0][0], arrays[0][1], decoder=decoder, model=model)

    def pack():
        for _ in range(count):
            video._pack(pair.left.color, pair.right.color, "sbsl", 8)
    packed = video._pack(pair.left.color, pair.right.color, "sbsl", 8)[0]

    def encode():
        av = _media.av()
        with av.open(os.path.join(folder, "encode.mp4"), "w") as out:
            stream = out.add_stream("libx264", rate=24)
            stream.width, stream.height, stream.pix_fmt = 2 * width, height, "yuv420p"
            stream.options = dict(job.outputs[0].options)  # convert's own: CRF 18, cpu-independent, ...
            for i in range(count):
                frame = _media.to_video_frame(packed, job.working, "yuv420p", job.colorspace)
                frame.pts = i
                for packet in stream.encode(frame):
                    out.mux(packet)
            for packet in stream.encode(None):
                out.mux(packet)

    def end_to_end(workers):
        def run():
            video.convert(color_path, depth_path, os.path.join(folder, f"sbs{workers}.mp4"), workers=workers,
                          threads=None if workers else args.threads or None, **CAMERA)
        return run

    stages = [("decoding (colour + depth)", decode), ("reprojection (warp_pair)", reproject_all),
              ("packing (sbsl)", pack), ("encoding (x264, CRF 18)", encode),
              ("end to end, one process", end_to_end(None)), ("end to end, --workers 2", end_to_end(2))]
    print(f"{count} frames of {width}x{height}, median of {args.repeats} runs, library threads "
          f"{args.threads or 'all'} (stages); CPU: {_cpu()}")
    for name, function in stages:
        seconds = timed(function, args.repeats)
        rates = sorted(count / s for s in seconds)
        print(f"  {name:28s} {statistics.median(rates):8.1f} frames/s   (runs: {', '.join(f'{r:.1f}' for r in rates)})")


def _cpu():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown"


if __name__ == "__main__":
    main()
