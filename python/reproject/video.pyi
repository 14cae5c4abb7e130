# Types of reproject.video (documented at run time: help(reproject.video.convert)).
import os
from typing import Callable, Literal, TypedDict

from . import Arch, EdgeMode, Encoding, HoleFill, Method

Layout = Literal["sbsl", "sbsr", "sbs2l", "sbs2r", "abl", "abr", "ab2l", "ab2r", "anaglyph", "left", "right",
                 "separate"]
Codec = Literal["libx264", "libx265", "ffv1"]
ConvertDirection = Literal["centre", "left-to-right", "right-to-left", "left_to_right", "right_to_left"]
_Path = str | os.PathLike[str]

layouts: tuple[str, ...]
codecs: tuple[str, ...]

ConvertErrorKind = Literal["settings", "input", "output", "failure"]

class ConvertError(ValueError):
    kind: ConvertErrorKind
    def __init__(self, message: str, kind: ConvertErrorKind = "settings") -> None: ...

class _SceneCamera(TypedDict):
    encoding: Literal["linear"]
    depth_scale: float
    separation: float
    convergence: float

def convert(color: _Path, depth: _Path, out: _Path, *, layout: Layout = "sbsl", suffix: bool = False,
            codec: Codec | None = None, pixel_format: str | None = None, crf: int | None = None,
            fps: float | None = None, encoding: Encoding | None = None, near: float | None = None,
            far: float | None = None, depth_scale: float | None = None, unknown_depth: float | str | None = None,
            separation: float | None = None, convergence: float | None = None, interaxial: float | None = None,
            fov: float | None = None, relative_depth: bool = False, max_parallax: float | None = None,
            zero_plane: float | None = None, disparity: bool = False, direction: ConvertDirection | None = None,
            method: Method = "exact", max_negative_parallax: float | None = None, hole_threshold: float = 1.0,
            hole_fill: HoleFill = "background", edge: EdgeMode = "clamp", dilate_depth: int = 0,
            probe_parallax: float | None = None, march_steps: int = 16, secant_max_steps: int = 256,
            arch: Arch | None = None, threads: int | None = None, segment_frames: int | None = None,
            resume: bool = False, workers: int | None = None, scheduler: str | None = None, retries: int = 2,
            progress: Callable[[int, int], object] | None = None, quiet: bool = True) -> list[str]: ...
def scene_video(out_dir: _Path, *, scene: str = "room", width: int = 640, height: int = 360, frames: int = 48,
                fps: int = 24, sway: float = 2.0, fov: float = 60.0, quiet: bool = True) -> _SceneCamera: ...
