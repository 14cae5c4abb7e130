"""Whole sequences and videos: colour + depth in, a stereo video or image sequence out.

    import reproject.video
    reproject.video.convert("shot.mp4", "shot_depth.mkv", "shot_3d.mkv", relative_depth=True,
                            max_parallax=0.03, zero_plane=0.5, layout="sbsl")

The command-line face is `python3 -m reproject convert` (docs/CLI.md "convert"). Frames stream
through PyAV one at a time (memory does not grow with the length); the work is cut into segments
that are encoded into their own files under a temporary name, renamed when complete, joined
without re-encoding, and only then is the output renamed into place with every audio and subtitle
stream of the colour input copied packet for packet and the input's timestamps kept. Segments can
run on a local Dask cluster or any dask.distributed scheduler, and --resume skips the finished ones.
"""
import contextlib
import dataclasses
import hashlib
import heapq
import json
import math
import numbers
import os
import shutil
import time

import numpy as np

from . import _media
from ._media import MediaError as _MediaError

__all__ = ["ConvertError", "convert", "layouts", "codecs", "scene_video"]

layouts = ("sbsl", "sbsr", "sbs2l", "sbs2r", "abl", "abr", "ab2l", "ab2r", "anaglyph", "left", "right", "separate")
codecs = ("libx264", "libx265", "ffv1")

# The file-name suffixes players read the layout from (suffix=True).
_SUFFIX = {"sbsl": "_LRF_Full_SBS", "sbsr": "_RLF_Full_SBS", "sbs2l": "_LR", "sbs2r": "_RL", "abl": "_TBF_Full_TB",
           "abr": "_BTF_Full_TB", "ab2l": "_TB", "ab2r": "_BT", "anaglyph": "_Anaglyph", "left": "_L", "right": "_R"}
# Matroska's StereoMode, as FFmpeg's muxer names it; and x264's frame-packing SEI.
_STEREO_MODE = {"sbsl": "left_right", "sbs2l": "left_right", "sbsr": "right_left", "sbs2r": "right_left",
                "abl": "top_bottom", "ab2l": "top_bottom", "abr": "bottom_top", "ab2r": "bottom_top",
                "anaglyph": "anaglyph_cyan_red"}
_FRAME_PACKING = {"sbsl": 3, "sbs2l": 3, "sbsr": 3, "sbs2r": 3, "abl": 4, "ab2l": 4, "abr": 4, "ab2r": 4}
_DEFAULT_CRF = {"libx264": 18, "libx265": 20}
_VIDEO_EXTENSIONS = (".mkv", ".mp4", ".mov", ".m4v", ".avi", ".nut", ".webm")
# Dubois' red-cyan least-squares matrices (rows: output R, G, B; columns: input r, g, b), as the
# CLI's pair --anaglyph uses them (tools/imageio).
_DUBOIS_LEFT = np.array([[0.456100, 0.500484, 0.176381], [-0.0400822, -0.0378246, -0.0157589],
                         [-0.0152161, -0.0205971, -0.00546856]], np.float32)
_DUBOIS_RIGHT = np.array([[-0.0434706, -0.0879388, -0.00155529], [0.378476, 0.73364, -0.0184503],
                          [-0.0721527, -0.112961, 1.2264]], np.float32)


class ConvertError(ValueError):
    """A conversion that cannot be done: bad input, bad settings or an output that cannot be
    written. The message names the file and, for a frame, its number; nothing is left behind.

    kind: which, as the command line's exit codes group them (docs/CLI.md "convert"): 'settings'
    (2: flags that are unknown, out of range or conflicting, an output that is an input or cannot
    hold the result), 'input' (3: an input missing, unreadable, corrupt or not matching the other),
    'output' (4: an output that cannot be written) or 'failure' (1: the library refused a frame, a
    dependency is missing, the cluster failed)."""

    def __init__(self, message, kind="settings"):
        super().__init__(message)
        self.kind = kind

    def __reduce__(self):  # the kind survives the trip back from a Dask worker
        return (type(self), (str(self), self.kind))


def _from_media(error):
    return ConvertError(str(error), error.kind)


@dataclasses.dataclass
class _Output:
    path: str          # the final file, or the printf pattern of an image sequence
    tag: str           # "out", "L" or "R": the name of its parts
    images: bool
    extension: str
    codec: str = ""
    pixel_format: str = ""
    options: dict = dataclasses.field(default_factory=dict)
    tags: dict = dataclasses.field(default_factory=dict)
    stereo_mode: str = ""


@dataclasses.dataclass
class _Job:
    color: _media.Source
    depth: _media.Source
    outputs: list
    layout: str
    working: tuple
    colorspace: object
    decoder: tuple
    model: tuple
    pair: bool
    left_to_right: bool
    depth_scale: object
    unknown_depth: object
    dilate_depth: int
    warp_options: dict
    segments: list
    parts: str
    first_number: int
    threads: int = 0


# ---- The camera ------------------------------------------------------------------------------------

def _camera(job, width):
    """The decoder and the parallax model, rebuilt in each process from plain values."""
    from . import Decoder, ParallaxModel, StereoCamera
    kind = job.decoder[0]
    decoder = Decoder.disparity() if kind == "disparity" else Decoder(kind, *job.decoder[1:])
    model_kind, *values = job.model
    direction = "centre-to-right" if job.pair else ("left-to-right" if job.left_to_right else "right-to-left")
    if model_kind == "relative":
        return decoder, ParallaxModel.from_relative(values[0], values[1], width, direction)
    if model_kind == "disparity":
        return decoder, ParallaxModel.from_disparity(direction)
    return decoder, StereoCamera(values[0], values[1]).parallax(width, direction)


def _resolve_camera(encoding, near, far, separation, convergence, interaxial, fov, relative_depth, max_parallax,
                    zero_plane, disparity, direction):
    def forbid(names, why):
        for name, value in names.items():
            if value is not None and value is not False:
                raise ConvertError(f"{name} cannot be used with {why}")
    if direction not in (None, "centre", "left-to-right", "right-to-left", "left_to_right", "right_to_left"):
        raise ConvertError(f"unknown direction '{direction}' (centre, left-to-right, right-to-left): convert keeps "
                           "the given eye or makes both from a centre view")
    direction = None if direction in (None, "centre") else direction.replace("_", "-")
    camera = dict(separation=separation, convergence=convergence, interaxial=interaxial, fov=fov)
    if relative_depth:
        forbid(dict(encoding=encoding, near=near, far=far, disparity=disparity, **camera),
               "relative_depth (max_parallax and zero_plane set the parallax)")
        decoder = ("disparity",)
        model = ("relative", 0.03 if max_parallax is None else float(max_parallax),
                 0.5 if zero_plane is None else float(zero_plane))
    else:
        forbid(dict(max_parallax=max_parallax, zero_plane=zero_plane), "a depth that is not relative_depth")
        if disparity or encoding == "disparity":
            forbid(dict(near=near, far=far, **camera), "a disparity map (the disparity is the parallax)")
            if direction is None:
                direction = "left-to-right"
            decoder, model = ("disparity",), ("disparity",)
        else:
            if encoding is None:
                raise ConvertError("the depth needs encoding= (--encoding), or relative_depth or disparity")
            decoder = (encoding, near, far)
            if convergence is None:
                raise ConvertError("convergence= (--convergence) is required with depth")
            if interaxial is not None or fov is not None:
                forbid(dict(separation=separation), "interaxial and fov (the rig gives the separation)")
                if interaxial is None or fov is None:
                    raise ConvertError("interaxial and fov go together (a renderer's rig)")
                if not 0 < fov < 180:
                    raise ConvertError(f"fov {fov} is not in (0, 180) degrees")
                from . import StereoCamera
                try:
                    separation = StereoCamera.from_rig(interaxial, convergence, math.radians(fov)).separation
                except ValueError as error:
                    raise ConvertError(str(error)) from None
            model = ("stereo", 0.03 if separation is None else float(separation), float(convergence))
    return decoder, model, direction


# ---- Planning ---------------------------------------------------------------------------------------

def _same_file(a, b):
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def _output_specs(out, layout, suffix, codec, pixel_format, crf, job_tags, working, width, height, color):
    base, extension = os.path.splitext(os.fspath(out))
    extension = extension.lower()
    images = "%" in os.fspath(out)
    if not images and extension not in _VIDEO_EXTENSIONS:
        raise ConvertError(f"output '{out}': a video ({', '.join(_VIDEO_EXTENSIONS)}) or an image sequence pattern "
                           "(frames/%04d.png, .exr)")
    if images and extension not in (".png", ".exr"):
        raise ConvertError(f"output '{out}': image sequences are written as .png or .exr")
    names = [("out", base + (_SUFFIX[layout] if suffix and layout != "separate" else ""))]
    if layout == "separate":
        names = [("L", base + "_L"), ("R", base + "_R")]
    packed_w = {"sbsl": 2 * width, "sbsr": 2 * width, "sbs2l": width // 2 * 2, "sbs2r": width // 2 * 2}.get(layout, width)
    packed_h = {"abl": 2 * height, "abr": 2 * height, "ab2l": height // 2 * 2, "ab2r": height // 2 * 2}.get(layout, height)
    specs = []
    for tag, name in names:
        spec = _Output(path=name + extension, tag=tag, images=images, extension=extension)
        if not images:
            _video_settings(spec, codec, pixel_format, crf, job_tags, working, packed_w, packed_h, layout, color)
        specs.append(spec)
    return specs


def _video_settings(spec, codec, pixel_format, crf, tags, working, width, height, layout, color):
    av = _media.av()
    spec.codec = codec or "libx264"
    if spec.codec not in codecs:
        raise ConvertError(f"unknown codec '{spec.codec}' ({', '.join(codecs)})")
    if spec.codec == "ffv1" and spec.extension in (".mp4", ".mov", ".m4v", ".webm"):
        raise ConvertError(f"output '{spec.path}': ffv1 is not carried by {spec.extension}; write .mkv")
    supported = [f.name for f in av.Codec(spec.codec, "w").video_formats]
    kind, bits, planar = working
    if pixel_format is None:
        source = color.family.name if color.family is not None and kind == "yuv" else ""
        if source in supported:
            pixel_format = source
        elif spec.codec == "ffv1":
            pixel_format = "bgr0" if bits == 8 and kind == "rgb" else (planar if planar in supported else "gbrp16le")
        else:
            pixel_format = "yuv420p" if bits == 8 else "yuv420p10le"
    if pixel_format not in supported:
        raise ConvertError(f"pixel format '{pixel_format}' is not one {spec.codec} writes ({', '.join(supported)})")
    if ("420" in pixel_format and (width % 2 or height % 2)) or ("422" in pixel_format and width % 2):
        raise ConvertError(f"output '{spec.path}' would be {width}x{height}: {pixel_format} needs even sizes "
                           "(use a 4:4:4 pixel format)")
    spec.pixel_format = pixel_format
    options = {}
    if spec.codec in _DEFAULT_CRF:
        options["crf"] = str(_DEFAULT_CRF[spec.codec] if crf is None else crf)
    elif crf is not None:
        raise ConvertError(f"crf is for libx264 and libx265, not {spec.codec} (lossless)")
    if spec.codec == "libx265":
        options["x265-params"] = "log-level=error"
    if spec.codec == "libx264":
        # cpu-independent: x264's macroblock-tree propagation in its C form. Its AVX-512 form reads
        # memory it never wrote (picture widths that are not a multiple of 128 pixels), so the
        # bitstream varied from run to run and a resumed output with it (docs/CLI.md "convert").
        params = ["cpu-independent=1"]
        if layout in _FRAME_PACKING:
            params.append(f"frame-packing={_FRAME_PACKING[layout]}")
        options["x264-params"] = ":".join(params)
    spec.tags = dict(tags) if _media.Family(pixel_format).kind == "yuv" else {
        k: v for k, v in tags.items() if k in ("color_primaries", "color_trc")}
    options.update(spec.tags)
    spec.options = options
    spec.stereo_mode = _STEREO_MODE.get(layout, "") if spec.extension == ".mkv" else ""


def _plan(color, depth, out, layout, suffix, codec, pixel_format, crf, fps, camera, depth_scale, unknown_depth,
          dilate_depth, warp_options, segment_frames, threads):
    if layout not in layouts:
        raise ConvertError(f"unknown layout '{layout}' ({', '.join(layouts)})")
    color_source = _media.Source("colour", color, fps)
    depth_source = _media.Source("depth", depth, fps)
    c, d = color_source, depth_source
    if (c.width, c.height) != (d.width, d.height):
        raise ConvertError(f"colour '{c.path}' is {c.width}x{c.height} but depth '{d.path}' is {d.width}x{d.height}",
                           "input")
    if c.count != d.count:
        raise ConvertError(f"colour '{c.path}' has {c.count} frames but depth '{d.path}' has {d.count}", "input")
    if c.kind == "video" and d.kind == "video":
        tolerance = 0.5 / float(max(c.rate or 1, d.rate or 1, 1))
        late = np.flatnonzero(np.abs(c.seconds() - d.seconds()) > tolerance)
        if late.size:
            i = int(late[0])
            raise ConvertError(f"depth '{d.path}' frame {i} is at {d.seconds()[i]:.4f} s but colour '{c.path}' frame {i} "
                               f"at {c.seconds()[i]:.4f} s (rates {float(d.rate or 0):g} and {float(c.rate or 0):g} fps)", "input")
    if d.family is not None and d.family.kind != "gray":
        raise ConvertError(f"depth '{d.path}' is {d.family.name}, not grey: depth must be one channel (gray, gray16le, "
                           "...)", "input")
    decoder, model, direction = camera
    images_out = "%" in os.fspath(out)
    as_yuv = c.kind == "video" and c.family.kind == "yuv" and not images_out and layout != "anaglyph"
    working = _media.working_form(c, "yuv" if as_yuv else "rgb")
    tags = dict(c.tags)
    if c.kind == "images" or not tags:
        tags = {"color_primaries": "bt709", "color_trc": "iec61966-2-1" if c.kind == "images" else "bt709",
                "colorspace": "bt709", "color_range": "tv"}
    outputs = _output_specs(out, layout, suffix, codec, pixel_format, crf, tags, working, c.width, c.height, c)
    inputs = [c.path] if c.files is None else list(c.files)
    inputs += [d.path] if d.files is None else list(d.files)
    first_number = _first_number(c)
    for spec in outputs:
        finals = [spec.path % (first_number + i) for i in range(c.count)] if spec.images else [spec.path]
        for final in finals[:1] + finals[-1:] if len(inputs) > 64 else finals:
            for source in inputs:
                if _same_file(final, source):
                    raise ConvertError(f"output '{final}' is the input '{source}' (an output must not replace an input)")
        if spec.images:
            input_set = {os.path.realpath(p) for p in inputs}
            clash = next((f for f in finals if os.path.realpath(f) in input_set), None)
            if clash:
                raise ConvertError(f"output '{clash}' is an input (an output must not replace an input)")
        _check_writable(finals[0], folder_made=spec.images)
    size = segment_frames or 250
    if size < 1:
        raise ConvertError(f"segment_frames {segment_frames} must be >= 1")
    segments = [(s, min(s + size, c.count)) for s in range(0, c.count, size)]
    first = outputs[0].path
    parts = (os.path.join(os.path.dirname(first) or ".", ".reproject-parts") if outputs[0].images
             else first + ".reproject-parts")
    direction_pair = direction is None
    return _Job(color=c, depth=d, outputs=outputs, layout=layout, working=working,
                colorspace=_media.colorspace_of(tags), decoder=decoder, model=model, pair=direction_pair,
                left_to_right=direction != "right-to-left", depth_scale=depth_scale, unknown_depth=unknown_depth,
                dilate_depth=dilate_depth, warp_options=warp_options, segments=segments, parts=parts,
                first_number=first_number, threads=threads)


def _check_writable(path, folder_made):
    """An output that cannot be written is refused before any work (as the CLI's outputs are,
    docs/CLI.md): a folder that is missing (an image sequence's is made) or not a folder, a
    directory or a device where the file would go."""
    folder = os.path.dirname(path) or "."
    if os.path.exists(path) and not os.path.isfile(path):
        what = "a directory" if os.path.isdir(path) else "not a regular file"
        raise ConvertError(f"cannot write '{path}': it is {what}", "output")
    while folder_made and not os.path.exists(folder):
        folder = os.path.dirname(folder) or "."
    if not os.path.isdir(folder):
        raise ConvertError(f"cannot write '{path}': " + (f"'{folder}' is not a folder" if os.path.exists(folder)
                                                         else f"the folder '{folder}' does not exist"), "output")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ConvertError(f"cannot write '{path}': the folder '{folder}' is not writable", "output")


def _first_number(source):
    if source.files is None or "%" not in source.path:
        return 0
    import re
    digits = re.findall(r"\d+", os.path.basename(source.files[0]))
    return int(digits[-1]) if digits else 0


def _fingerprint(job):
    def stat(path):
        info = os.stat(path)
        return [path, info.st_size, info.st_mtime_ns]
    sources = []
    for source in (job.color, job.depth):
        files = source.files if source.files is not None else [source.path]
        sources.append([stat(files[0]), stat(files[-1]), len(files)])
    from . import __version__
    settings = dict(version=__version__, sources=sources, layout=job.layout, working=list(job.working),
                    outputs=[dataclasses.asdict(o) for o in job.outputs], decoder=job.decoder, model=job.model,
                    pair=job.pair, left_to_right=job.left_to_right, depth_scale=job.depth_scale,
                    unknown_depth=str(job.unknown_depth), dilate_depth=job.dilate_depth,
                    warp=job.warp_options, segments=job.segments)
    return hashlib.sha256(json.dumps(settings, sort_keys=True, default=str).encode()).hexdigest()


# ---- One frame --------------------------------------------------------------------------------------

def _fill_unknown(depth, unknown, decoder):
    """Runs of unknown depth take the farther (smaller 1/z) of their nearest known row neighbours, as
    the CLI's --unknown-depth does (docs/CLI.md); a row without any known value the farthest value."""
    height, width = depth.shape
    columns = np.arange(width)
    left = np.maximum.accumulate(np.where(unknown, -1, columns), axis=1)
    right = np.minimum.accumulate(np.where(unknown, width, columns)[:, ::-1], axis=1)[:, ::-1]
    rows = np.arange(height)[:, None]
    left_value = depth[rows, np.clip(left, 0, width - 1)]
    right_value = depth[rows, np.clip(right, 0, width - 1)]
    encoding = decoder.encoding
    farthest = {"disparity": 0.0, "linear": np.inf}.get(encoding)
    if farthest is None:
        farthest = decoder.encode(math.inf if encoding in ("reversed_infinite", "infinite") else decoder.far)
    farther = np.where(decoder.inverse_depth(left_value) <= decoder.inverse_depth(right_value), left_value, right_value)
    value = np.where(left >= 0, np.where(right < width, farther, left_value),
                     np.where(right < width, right_value, np.float32(farthest)))
    depth[unknown] = value[unknown]


def _depth_values(job, frame, index, decoder):
    values, top = _media.depth_array(job.depth, frame, index)
    unknown = None
    if job.unknown_depth is not None:
        unknown = np.isnan(values) if job.unknown_depth == "nan" else values == np.float32(job.unknown_depth)
    scale = job.depth_scale if job.depth_scale is not None else (1.0 / top if job.model[0] == "relative" else 1.0)
    if scale != 1.0:
        values *= np.float32(scale)
    if unknown is not None and unknown.any():
        _fill_unknown(values, unknown, decoder)
    if job.dilate_depth:
        from . import dilate_nearer_depth
        values = dilate_nearer_depth(values, decoder, job.dilate_depth)
    return values


def _squeeze(picture, axis):
    count = picture.shape[axis] // 2 * 2
    even = np.take(picture, np.arange(0, count, 2), axis=axis)
    odd = np.take(picture, np.arange(1, count, 2), axis=axis)
    if picture.dtype == np.uint8:
        return ((even.astype(np.uint16) + odd + 1) >> 1).astype(np.uint8)
    return (even + odd) * np.float32(0.5)


def _anaglyph(left, right, bits):
    if left.dtype == np.uint8:
        l, r = left[..., :3].astype(np.float32), right[..., :3].astype(np.float32)
        mixed = l @ _DUBOIS_LEFT.T + r @ _DUBOIS_RIGHT.T
        out = np.empty(left.shape, np.uint8)
        out[..., :3] = np.clip(np.rint(mixed), 0, 255)
        out[..., 3] = 255
        return out
    mixed = np.einsum("kc,chw->khw", _DUBOIS_LEFT, left[:3]) + np.einsum("kc,chw->khw", _DUBOIS_RIGHT, right[:3])
    return np.clip(mixed, 0, 1.0 if bits == 32 else float((1 << bits) - 1)).astype(np.float32)


def _pack(left, right, layout, bits):
    """The pictures of a layout (ffmpeg's stereo3d names), one per output."""
    packed = left.dtype == np.uint8
    w_axis, h_axis = (1, 0) if packed else (2, 1)
    first, second = (right, left) if layout in ("sbsr", "sbs2r", "abr", "ab2r") else (left, right)
    if layout in ("sbsl", "sbsr"):
        return [np.concatenate([first, second], axis=w_axis)]
    if layout in ("sbs2l", "sbs2r"):
        return [np.concatenate([_squeeze(first, w_axis), _squeeze(second, w_axis)], axis=w_axis)]
    if layout in ("abl", "abr"):
        return [np.concatenate([first, second], axis=h_axis)]
    if layout in ("ab2l", "ab2r"):
        return [np.concatenate([_squeeze(first, h_axis), _squeeze(second, h_axis)], axis=h_axis)]
    if layout == "anaglyph":
        return [_anaglyph(left, right, bits)]
    return {"left": [left], "right": [right], "separate": [left, right]}[layout]


# ---- Segments ---------------------------------------------------------------------------------------

def _part_path(job, spec, index, temporary=False):
    # Video parts are files of the output's container: they keep every packet's presentation
    # timestamp (Matroska unshifted, below) and the decoding order; the join gives the packets
    # their decoding timestamps again (_packets_in_order).
    name = f"{spec.tag}-{index:06d}" + ("" if spec.images else ".nut")
    return os.path.join(job.parts, ("." + name + ".tmp") if temporary else name)


class _VideoPart:
    def __init__(self, job, spec, index):
        av = _media.av()
        self.job, self.spec = job, spec
        self.final = _part_path(job, spec, index)
        self.temporary = _part_path(job, spec, index, temporary=True)
        self.temporary = self.temporary + ".nut"
        self.container = av.open(self.temporary, "w",
                                 format="nut", options={"avoid_negative_ts": "disabled", "fflags": "+bitexact"})
        source = job.color
        self.stream = self.container.add_stream(spec.codec, rate=source.rate)
        self.stream.codec_context.time_base = source.time_base
        self.stream.options = dict(spec.options)
        self.frames = 0

    def write(self, picture, index):
        frame = _media.to_video_frame(picture, self.job.working, self.spec.pixel_format, self.job.colorspace)
        if self.frames == 0:
            self.stream.width, self.stream.height = frame.width, frame.height
            self.stream.pix_fmt = self.spec.pixel_format
        frame.pts = int(self.job.color.pts[index])
        frame.time_base = self.job.color.time_base
        for packet in self.stream.encode(frame):
            self.container.mux(packet)
        self.frames += 1

    def close(self):
        for packet in self.stream.encode(None):
            self.container.mux(packet)
        self.container.close()
        os.replace(self.temporary, self.final)

    def abort(self):
        with contextlib.suppress(Exception):
            self.container.close()
        with contextlib.suppress(OSError):
            os.remove(self.temporary)


class _ImagePart:
    def __init__(self, job, spec, index):
        self.job, self.spec = job, spec
        self.final = _part_path(job, spec, index)
        self.temporary = _part_path(job, spec, index, temporary=True)
        shutil.rmtree(self.temporary, ignore_errors=True)
        os.makedirs(self.temporary)
        self.context = None

    def write(self, picture, index):
        av = _media.av()
        frame = _media.to_image_frame(picture, self.job.working, self.spec.extension)
        context = av.CodecContext.create("exr" if self.spec.extension == ".exr" else "png", "w")
        context.width, context.height, context.pix_fmt = frame.width, frame.height, frame.format.name
        data = b"".join(bytes(p) for p in list(context.encode(frame)) + list(context.encode(None)))
        name = os.path.basename(self.spec.path % (self.job.first_number + index))
        with open(os.path.join(self.temporary, name), "wb") as f:
            f.write(data)

    def close(self):
        os.replace(self.temporary, self.final)

    def abort(self):
        shutil.rmtree(self.temporary, ignore_errors=True)


def _segment(job, index, on_frame=None):
    """Converts one segment into its part files (one per output): the unit of work of every run."""
    from . import warp, warp_pair
    start, stop = job.segments[index]
    if all(os.path.exists(_part_path(job, spec, index)) for spec in job.outputs):
        return stop - start
    decoder, model = _camera(job, job.color.width)
    parts = []
    options = dict(job.warp_options, threads=job.threads)
    try:
        parts = [(_ImagePart if spec.images else _VideoPart)(job, spec, index) for spec in job.outputs]
        previous = None
        color_frames, depth_frames = job.color.frames(start, stop), job.depth.frames(start, stop)
        with contextlib.closing(color_frames), contextlib.closing(depth_frames):
            for offset, (color_frame, depth_frame) in enumerate(zip(color_frames, depth_frames)):
                i = start + offset
                color = _media.color_array(color_frame, job.working, job.colorspace)
                depth = _depth_values(job, depth_frame, i, decoder)
                try:
                    if job.pair:
                        previous = warp_pair(color, depth, decoder=decoder, model=model, **options,
                                             out_left=previous.left if previous else None,
                                             out_right=previous.right if previous else None)
                        left, right = previous.left.color, previous.right.color
                    else:
                        previous = warp(color, depth, decoder=decoder, model=model, **options, out=previous)
                        left, right = (color, previous.color) if job.left_to_right else (previous.color, color)
                except ValueError as error:
                    raise ConvertError(f"{job.color.describe(i)}: {error}", "failure") from None
                for part, picture in zip(parts, _pack(left, right, job.layout, job.working[1])):
                    part.write(picture, i)
                if on_frame:
                    on_frame()
        for part in parts:
            part.close()
    except _MediaError as error:
        for part in parts:
            part.abort()
        raise _from_media(error) from None
    except (OSError, _media.av().AVError) as error:  # reading errors are MediaErrors by now
        for part in parts:
            part.abort()
        raise ConvertError(f"cannot write segment {index} into '{job.parts}': {error}", "output") from None
    except BaseException:
        for part in parts:
            part.abort()
        raise
    return stop - start


def _segment_task(job, index):
    """A Dask task: one segment, in a worker process (it opens and seeks the inputs itself)."""
    return _segment(job, index)


# ---- Joining ----------------------------------------------------------------------------------------

def _packets_in_order(job, parts):
    """The parts' video packets in decoding order, with decoding timestamps. A reordering codec
    (B-frames) decodes each packet at most D packets before its frame is shown (D, the reorder
    delay, measured here); with every frame's timestamp known (the colour input's, sorted), the
    i-th packet's decoding time is the (i - D)-th timestamp: never after the packet's own, and
    increasing across the parts' boundaries as within them."""
    av = _media.av()
    base, pts = job.color.time_base, job.color.pts

    def packets():
        for path in parts:
            with av.open(path) as container:
                for packet in container.demux(container.streams.video[0]):
                    if packet.size:
                        yield packet
    delay, count = 0, 0
    for packet in packets():
        rank = int(np.searchsorted(pts, round(packet.pts * packet.time_base / base)))
        delay, count = max(delay, count - rank), count + 1
    if count != len(pts):
        raise ConvertError(f"the parts in '{job.parts}' hold {count} frames, not {len(pts)}", "output")
    step = int(pts[1] - pts[0]) if len(pts) > 1 else 1
    for i, packet in enumerate(packets()):
        decoding = int(pts[i - delay]) if i >= delay else int(pts[0]) - (delay - i) * max(step, 1)
        packet.dts = round(decoding * base / packet.time_base)
        yield packet


def _time_of(packet):
    stamp = packet.dts if packet.dts is not None else packet.pts
    return float(stamp * packet.time_base) if stamp is not None else -math.inf


def _join_video(job, spec, temporary):
    """The parts, joined without re-encoding, with the colour input's audio and subtitle streams
    copied packet for packet, into `temporary`."""
    av = _media.av()
    parts = [_part_path(job, spec, i) for i in range(len(job.segments))]
    # Timestamps as they are; no random or dated fields, so the same parts always give the same bytes.
    options = {"avoid_negative_ts": "disabled"} if spec.extension == ".mkv" else {}
    options["fflags"] = "+bitexact"
    with av.open(parts[0]) as first, av.open(temporary, "w", options=options) as out, \
            contextlib.ExitStack() as stack:
        video = out.add_stream(template=first.streams.video[0])
        # NUT parts keep no colour tags: the output's stream gets them again from its settings.
        video.codec_context.options = dict(spec.tags)
        if spec.stereo_mode:
            video.metadata["stereo_mode"] = spec.stereo_mode
        sources, copies = [], []
        if job.color.kind == "video":
            color = stack.enter_context(av.open(job.color.path))
            for stream in color.streams:
                if stream.type in ("audio", "subtitle"):
                    copy = out.add_stream(template=stream)
                    copy.metadata.update(stream.metadata)
                    sources.append(stream)
                    copies.append(copy)
        mapping = {s.index: c for s, c in zip(sources, copies)}
        streams = [_packets_in_order(job, parts)]
        if sources:
            streams.append(p for p in color.demux(sources) if p.size)
        for packet in heapq.merge(*streams, key=_time_of):
            packet.stream = mapping.get(packet.stream_index, video) if packet.stream.type != "video" else video
            out.mux(packet)


# Set once a conversion starts renaming its outputs into place (_join): from then on the run has
# produced them, so `python3 -m reproject` lets a stopping signal pass instead of reporting the run
# as interrupted with no output left (__main__._stop). Cleared when a conversion starts.
_committing = False


def _outputs_committing():
    """Whether the running conversion has started putting its outputs into place."""
    return _committing


def _join(job):
    """Every output from its parts, to a temporary name; then all renamed into place together."""
    global _committing
    finished = []
    try:
        for spec in job.outputs:
            if spec.images:
                continue
            folder, name = os.path.split(spec.path)
            temporary = os.path.join(folder, f".{os.path.splitext(name)[0]}.reproject-tmp{os.getpid()}{spec.extension}")
            finished.append((temporary, spec.path))
            try:
                _join_video(job, spec, temporary)
            except (OSError, _media.av().AVError) as error:
                raise ConvertError(f"cannot write '{spec.path}': {error}", "output") from None
    except BaseException:
        for temporary, _ in finished:
            with contextlib.suppress(OSError):
                os.remove(temporary)
        raise
    _committing = True
    try:
        for temporary, final in finished:
            os.replace(temporary, final)
        for spec in job.outputs:
            if spec.images:
                folder = os.path.dirname(spec.path)
                if folder:
                    os.makedirs(folder, exist_ok=True)
                for index in range(len(job.segments)):
                    part = _part_path(job, spec, index)
                    for name in sorted(os.listdir(part)):
                        os.replace(os.path.join(part, name), os.path.join(folder, name))
    except OSError as error:
        raise ConvertError(f"cannot put the outputs into place: {error}", "output") from None


# ---- Running ----------------------------------------------------------------------------------------

def _prepare_parts(job, resume):
    manifest = os.path.join(job.parts, "manifest.json")
    fingerprint = _fingerprint(job)
    if resume and os.path.exists(manifest):
        with open(manifest) as f:
            if json.load(f).get("fingerprint") != fingerprint:
                raise ConvertError(f"'{job.parts}' holds the parts of another conversion (other inputs or settings): "
                                   "remove it, or run without resume")
        for name in os.listdir(job.parts):
            if name.startswith("."):
                path = os.path.join(job.parts, name)
                shutil.rmtree(path) if os.path.isdir(path) else os.remove(path)
        return
    if os.path.exists(manifest):
        shutil.rmtree(job.parts)
    try:
        os.makedirs(job.parts, exist_ok=True)
        with open(manifest + ".tmp", "w") as f:
            json.dump({"fingerprint": fingerprint}, f)
        os.replace(manifest + ".tmp", manifest)
    except OSError as error:
        raise ConvertError(f"cannot write the parts folder '{job.parts}': {error}", "output") from None


def _preflight(job):
    """Writes the header of each video output's container with the colour input's audio and
    subtitle streams once before any work, so that a stream the container cannot carry (FLAC in
    .mp4, say) fails at once and costs nothing."""
    if job.color.kind != "video":
        return
    av = _media.av()
    for spec in job.outputs:
        if spec.images:
            continue
        probe = os.path.join(job.parts, f".preflight{spec.extension}")
        try:
            with av.open(job.color.path) as color:
                copied = [s for s in color.streams if s.type in ("audio", "subtitle")]
                if not copied:
                    return
                with av.open(probe, "w") as out:
                    for stream in copied:
                        out.add_stream(template=stream)
                    out.start_encoding()
        except (av.AVError, ValueError) as error:
            raise ConvertError(f"output '{spec.path}' cannot carry the audio and subtitle streams of colour "
                               f"'{job.color.path}': {error}") from None
        finally:
            with contextlib.suppress(OSError):
                os.remove(probe)


def _run_local(job, todo, on_frame):
    for index in todo:
        _segment(job, index, on_frame)


def _run_dask(job, todo, workers, scheduler, retries, on_segment):
    try:
        import distributed
    except ImportError:
        raise ConvertError("workers= and scheduler= need Dask (Debian: python3-distributed)", "failure") from None
    import logging
    with contextlib.ExitStack() as stack:
        if scheduler:
            try:
                client = stack.enter_context(distributed.Client(scheduler, timeout=30))
            except (OSError, TimeoutError, ValueError) as error:
                raise ConvertError(f"cannot reach the Dask scheduler '{scheduler}': {error}", "failure") from None
        else:
            cluster = stack.enter_context(distributed.LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                host="127.0.0.1", silence_logs=logging.ERROR))
            client = stack.enter_context(distributed.Client(cluster))
        futures = client.map(_segment_task, [job] * len(todo), todo, retries=retries, pure=False)
        try:
            for future in distributed.as_completed(futures):
                try:
                    frames = future.result()
                except distributed.KilledWorker as error:
                    raise ConvertError(f"a segment's worker died {retries + 1} times, the last time with it: {error}",
                                       "failure") from None
                on_segment(frames)
        except BaseException:
            client.cancel(futures)
            raise


def convert(color, depth, out, *, layout="sbsl", suffix=False, codec=None, pixel_format=None, crf=None, fps=None,
            encoding=None, near=None, far=None, depth_scale=None, unknown_depth=None, separation=None,
            convergence=None, interaxial=None, fov=None, relative_depth=False, max_parallax=None, zero_plane=None,
            disparity=False, direction=None, method="exact", max_negative_parallax=None, hole_threshold=1.0,
            hole_fill="background", edge="clamp", dilate_depth=0, probe_parallax=None, march_steps=16,
            secant_max_steps=256, arch=None, threads=None, segment_frames=None, resume=False, workers=None,
            scheduler=None, retries=2, progress=None, quiet=True):
    """Converts a whole sequence or video: colour + depth in, a stereo video or image sequence out.

    color, depth: a video file, an image sequence as a printf pattern ('frames/%04d.exr') or a
      directory of images in name order (.png, .exr, .pfm, .tif, .jpg, ...). Depth is one channel:
      a grey video or image (a 16-bit grey frame is read as integers, like a 16-bit PNG), or an
      EXR's Z. Both must have the same size and frame count, and two videos the same timestamps.
    out: a video (.mkv, .mp4, .mov, ...) or an image sequence pattern ('out/%04d.png', .exr).
    layout: 'sbsl' (the default), 'sbsr', 'sbs2l', 'sbs2r', 'abl', 'abr', 'ab2l', 'ab2r' as
      ffmpeg's stereo3d names them (sbs side by side, ab above-below, 2 half size, l/r the eye first),
      'anaglyph' (Dubois red-cyan), 'left', 'right', or 'separate' (two outputs, name_L and name_R).
    suffix: add the players' layout suffix to the output name ('_LRF_Full_SBS', '_LR', '_TB', ...).
    codec: 'libx264' (default), 'libx265' or 'ffv1' (lossless); pixel_format: any the codec writes
      (default: the input's when the codec writes it, else yuv420p or yuv420p10le); crf: x264/x265
      quality [18 / 20]. The colour input's primaries, transfer, matrix and range are carried over.
    fps: the frame rate of image sequences [25].
    The camera, as the CLI's warp and pair take it (docs/CLI.md): encoding=, near=, far=,
      depth_scale= (stored values times K [1]), unknown_depth= (a stored value, or 'nan', that means
      no depth), separation= [0.03] and convergence=, or interaxial= and fov= (degrees: a renderer's
      rig, StereoCamera.from_rig), or relative_depth=True with max_parallax= [0.03] and zero_plane=
      [0.5] (a monocular model's relative inverse depth, 0 farthest .. 1 nearest; integer frames read
      as a fraction of their largest code), or disparity=True. direction=None or 'centre': both eyes
      from a centre view (warp_pair); 'left-to-right' / 'right-to-left': the given eye is kept.
    Reprojection options as warp's: method, max_negative_parallax, hole_threshold, hole_fill, edge,
      probe_parallax, march_steps, secant_max_steps, arch; dilate_depth (columns, the halo
      pre-filter); threads (the library's threads per frame; None: every core in one process, the
      cores shared out among a local cluster's workers, 1 per task with a scheduler).
    segment_frames: frames per segment [250]; resume: reuse the finished segments of an
      interrupted run with the same inputs and settings (kept in OUT.reproject-parts).
    workers: run the segments on a local Dask cluster of this many processes; scheduler: the
      address of a running dask.distributed scheduler (its workers must see the same files);
      retries: how often Dask reruns a failed segment.
    progress: a callable(done, total) called as frames complete; quiet=False: a tqdm bar on stderr.
    Returns the outputs written. Raises ConvertError (a ValueError) naming the file and frame;
    KeyboardInterrupt stops within a frame. Either way no partial output is left, and the parts
    folder only when resuming is possible (segment_frames or resume given).
    """
    global _committing  # set by _join (see _outputs_committing)
    for name, value in (("segment_frames", segment_frames), ("workers", workers)):
        if value is not None and (not isinstance(value, int) or value < 1):
            raise ConvertError(f"{name} must be an integer >= 1, not {value!r}")
    if not isinstance(retries, int) or retries < 0:
        raise ConvertError(f"retries {retries!r} must be an integer >= 0")
    if crf is not None and (not isinstance(crf, int) or not 0 <= crf <= 51):
        raise ConvertError(f"crf {crf!r} must be an integer in 0..51")
    if fps is not None and not (isinstance(fps, numbers.Real) and 0 < float(fps) < math.inf):
        raise ConvertError(f"fps {fps!r} must be a number > 0")
    if workers is not None and scheduler is not None:
        raise ConvertError("workers (a local cluster) and scheduler (a running one) cannot be used together")
    if unknown_depth is not None and unknown_depth != "nan":
        try:
            unknown_depth = float(unknown_depth)
        except (TypeError, ValueError):
            raise ConvertError(f"unknown_depth {unknown_depth!r} is neither a number nor 'nan'") from None
    if depth_scale is not None and not (depth_scale > 0 and math.isfinite(depth_scale)):
        raise ConvertError(f"depth_scale {depth_scale} must be finite and > 0")
    if not (isinstance(dilate_depth, int) and 0 <= dilate_depth <= 4096):
        raise ConvertError(f"dilate_depth {dilate_depth!r} must be an integer in 0..4096")
    camera = _resolve_camera(encoding, near, far, separation, convergence, interaxial, fov, relative_depth,
                             max_parallax, zero_plane, disparity, direction)
    warp_options = dict(method=method, max_negative_parallax=max_negative_parallax, hole_threshold=hole_threshold,
                        hole_fill=hole_fill, edge=edge, probe_parallax=probe_parallax, march_steps=march_steps,
                        secant_max_steps=secant_max_steps, arch=arch)
    if threads is None:
        threads = 0 if workers is None and scheduler is None else (
            max(1, (os.cpu_count() or 1) // workers) if workers else 1)
    try:
        job = _plan(color, depth, out, layout, suffix, codec, pixel_format, crf, fps, camera, depth_scale,
                    unknown_depth, dilate_depth, warp_options, segment_frames, threads)
        _check_camera(job)
    except _MediaError as error:
        raise _from_media(error) from None
    keep = resume or segment_frames is not None
    _committing = False
    _prepare_parts(job, resume)
    total = job.color.count
    bar = None
    try:
        _preflight(job)
        todo = [i for i, _ in enumerate(job.segments)
                if not all(os.path.exists(_part_path(job, spec, i)) for spec in job.outputs)]
        done = total - sum(job.segments[i][1] - job.segments[i][0] for i in todo)
        if not quiet:
            from tqdm import tqdm
            bar = tqdm(total=total, initial=done, unit="frame", dynamic_ncols=True, smoothing=0.1)
        state = {"done": done}

        def advance(frames=1):
            state["done"] += frames
            if bar is not None:
                bar.update(frames)
            if progress is not None:
                progress(state["done"], total)
        if workers is None and scheduler is None:
            _run_local(job, todo, advance)
        else:
            _run_dask(job, todo, workers, scheduler, retries, advance)
        _join(job)
    except BaseException as error:
        if bar is not None:
            bar.close()
        if not keep or isinstance(error, ConvertError) and "parts of another" not in str(error):
            shutil.rmtree(job.parts, ignore_errors=True)
        else:
            for name in os.listdir(job.parts) if os.path.isdir(job.parts) else []:
                if name.startswith("."):
                    path = os.path.join(job.parts, name)
                    shutil.rmtree(path, ignore_errors=True) if os.path.isdir(path) else os.remove(path)
        if isinstance(error, _MediaError):
            raise _from_media(error) from None
        raise
    if bar is not None:
        bar.close()
    shutil.rmtree(job.parts, ignore_errors=True)
    return [spec.path for spec in job.outputs]


def _check_camera(job):
    try:
        decoder, model = _camera(job, job.color.width)
        from . import warp
        probe = np.zeros((2, 2), np.float32)
        warp(probe, probe + (1.0 if job.decoder[0] not in ("disparity",) else 0.0), decoder=decoder, model=model,
             **dict(job.warp_options, threads=job.threads))
    except ValueError as error:
        raise ConvertError(str(error)) from None
    except TypeError as error:
        raise ConvertError(str(error)) from None


# ---- A sequence anyone can try --------------------------------------------------------------------

def scene_video(out_dir, *, scene="room", width=640, height=360, frames=48, fps=24, sway=2.0, fov=60.0,
                quiet=True):
    """Renders a built-in scene along a short camera path and writes colour, depth and the true eyes
    as lossless videos: a sequence to try convert() on, and to score it against the truth.

    The camera sways sideways (sway interaxials, a sine over the clip) with its convergence plane
    fixed. out_dir gets centre.mkv (colour, FFV1 RGB), depth.mkv (FFV1 16-bit grey: linear depth in
    thousandths of a view-space unit, i.e. encoding='linear', depth_scale=0.001), left.mkv and
    right.mkv (the true eyes), left_visible.mkv and right_visible.mkv (FFV1 grey: 255 where the
    eye's pixel is visible from the centre view too). Returns the convert() keywords that match the
    camera (separation, convergence, encoding, depth_scale).
    """
    from . import scene as render
    for name, value in (("width", width), ("height", height), ("frames", frames), ("fps", fps)):
        if not isinstance(value, int) or value < 1:
            raise ConvertError(f"{name} must be an integer >= 1, not {value!r}")
    try:
        render(scene, 2, 2, fov=fov, encoding="linear")  # the scene's name and the fov, before any file
    except ValueError as error:
        raise ConvertError(str(error)) from None
    av = _media.av()
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as error:
        raise ConvertError(f"cannot create the folder '{out_dir}': {error}", "output") from None
    names = ("centre", "depth", "left", "right", "left_visible", "right_visible")
    formats = {"depth": "gray16le", "left_visible": "gray", "right_visible": "gray"}
    streams, containers = {}, {}
    bar = None
    try:
        for name in names:
            container = av.open(os.path.join(out_dir, f".{name}.reproject-tmp.mkv"), "w")
            stream = container.add_stream("ffv1", rate=fps)
            stream.width, stream.height, stream.pix_fmt = width, height, formats.get(name, "bgr0")
            containers[name], streams[name] = container, stream
        if not quiet:
            from tqdm import tqdm
            bar = tqdm(total=frames, unit="frame")
        camera = None
        for k in range(frames):
            offset = sway * math.sin(2 * math.pi * k / max(frames, 1))
            s = render(scene, width, height, fov=fov, encoding="linear", offset=offset)
            camera = s.camera
            pictures = {"centre": s.color, "left": s.left, "right": s.right}
            for name, picture in pictures.items():
                rgb = np.clip(np.rint(picture[..., :3] * 255), 0, 255).astype(np.uint8)
                frame = av.VideoFrame.from_ndarray(np.ascontiguousarray(rgb), format="rgb24").reformat(format="bgr0")
                _encode(containers[name], streams[name], frame, k)
            millimetres = np.clip(np.rint(s.depth * 1000), 0, 65535).astype(np.uint16)
            _encode(containers["depth"], streams["depth"], av.VideoFrame.from_ndarray(millimetres, format="gray16le"), k)
            for name, mask in (("left_visible", s.left_visible), ("right_visible", s.right_visible)):
                grey = np.where(mask, 255, 0).astype(np.uint8)
                _encode(containers[name], streams[name], av.VideoFrame.from_ndarray(grey, format="gray"), k)
            if bar is not None:
                bar.update(1)
        for name in names:
            _encode(containers[name], streams[name], None, 0)
            containers[name].close()
        for name in names:
            os.replace(os.path.join(out_dir, f".{name}.reproject-tmp.mkv"), os.path.join(out_dir, f"{name}.mkv"))
    except BaseException as error:
        for name, container in containers.items():
            with contextlib.suppress(Exception):
                container.close()
            with contextlib.suppress(OSError):
                os.remove(os.path.join(out_dir, f".{name}.reproject-tmp.mkv"))
        if isinstance(error, (OSError, av.AVError)):
            raise ConvertError(f"cannot write into '{out_dir}': {error}", "output") from None
        raise
    finally:
        if bar is not None:
            bar.close()
    return dict(encoding="linear", depth_scale=0.001, separation=camera.separation, convergence=camera.convergence)


def _encode(container, stream, frame, index):
    if frame is not None:
        frame.pts = index
    for packet in stream.encode(frame):
        container.mux(packet)
