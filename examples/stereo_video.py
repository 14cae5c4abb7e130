"""A whole shot to a side-by-side 3D video: the built-in room along a short camera path
(reproject.video.scene_video), then converted (reproject.video.convert) and scored against the
true eyes. Run from the repository's root with the package importable:

    PYTHONPATH=build/python python3 examples/stereo_video.py out/sequence
"""
import sys

import numpy as np

import reproject.metrics
import reproject.video


def main(folder: str) -> None:
    camera = reproject.video.scene_video(folder, width=320, height=180, frames=24)

    def report(done: int, total: int) -> None:
        if done == total:
            print(f"{done} frames converted")
    left, right = reproject.video.convert(
        f"{folder}/centre.mkv", f"{folder}/depth.mkv", f"{folder}/eye.mkv", layout="separate", codec="ffv1",
        progress=report, **camera)
    reproject.video.convert(f"{folder}/centre.mkv", f"{folder}/depth.mkv", f"{folder}/sbs.mp4", layout="sbs2l",
                            suffix=True, encoding="linear", depth_scale=0.001, convergence=3.5)
    import av  # type: ignore[import]
    with av.open(right) as converted, av.open(f"{folder}/right.mkv") as truth:
        scores = [reproject.metrics.psnr(np.asarray(a.to_ndarray(format="rgb24")),
                                         np.asarray(b.to_ndarray(format="rgb24")))
                  for a, b in zip(converted.decode(video=0), truth.decode(video=0))]
    print(f"{left}, {right}: whole-frame PSNR against the true right eye {min(scores):.2f} .. {max(scores):.2f} dB")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/sequence")
