"""Frames in and out for reproject.video, through PyAV (Debian's python3-av; no ffmpeg process).

A source is a video file, an image sequence given as a printf pattern (frames/%04d.exr) or a
directory of images in name order. Sources are probed once (size, frame count, every frame's
timestamp, pixel format, colour tags), then each segment of work opens its own and seeks to its
first frame, so nothing but the segment's own frames is ever decoded twice and no pixels travel
between processes.

Colour is carried as one of two working forms (docs/CLI.md "convert"): 8-bit samples as an
(H, W, 4) uint8 array the library reprojects in place (rgba8, blending the stored codes), and more
bits as (C, H, W) float32 planes of the stored codes. A YUV video written back to a YUV video is
reprojected in YUV 4:4:4 (no colour matrix in between, so primaries, transfer, matrix and range,
HDR included, pass through untouched); everything else in RGB.
"""
import fractions
import os
import re

import numpy as np

from . import _exr

IMAGE_EXTENSIONS = (".png", ".exr", ".pfm", ".tif", ".tiff", ".jpg", ".jpeg", ".bmp", ".ppm", ".pgm")
_TAG_LINE = re.compile(r"Video: [^,]*(?:\([^)]*\))*[^,]*, (\w+)(?:\(([^)]*)\))?")
_RANGES = {"tv", "pc"}


class MediaError(Exception):
    """A source that cannot be used: the message names the file (and the frame). kind: as
    reproject.video.ConvertError's ('input', or 'failure' without PyAV)."""

    def __init__(self, message, kind="input"):
        super().__init__(message)
        self.kind = kind


def av():
    try:
        import av as module
    except ImportError:  # pragma: no cover - the package's optional dependency
        raise MediaError("reproject.video needs PyAV (Debian: python3-av)", "failure") from None
    module.logging.set_level(module.logging.PANIC)
    return module


def color_tags(container, index):
    """The stream's colour range, matrix, primaries and transfer, as FFmpeg names them (PyAV 10
    exposes none of them: they are read from FFmpeg's own description of the stream)."""
    logging = av().logging
    quiet = logging.get_level()
    logging.set_level(logging.INFO)  # the description is FFmpeg's log output
    try:
        text = container.dumps_format()
    finally:
        logging.set_level(quiet)
    lines = [line for line in text.splitlines() if f"Stream #0:{index}" in line]
    match = _TAG_LINE.search(lines[0]) if lines else None
    tags = {}
    if match and match.group(2):
        parts = [p.strip() for p in match.group(2).split(",")]
        if parts and parts[0] in _RANGES:
            tags["color_range"] = parts.pop(0)
        if parts and parts[0] not in ("progressive", "top first", "bottom first", "top coded first (swapped)",
                                      "bottom coded first (swapped)"):
            names = parts[0].split("/")
            if len(names) == 3:
                tags["colorspace"], tags["color_primaries"], tags["color_trc"] = names
            elif names[0] != "unknown":
                tags["colorspace"] = tags["color_primaries"] = tags["color_trc"] = names[0]
    # FFmpeg prints "bt709" for matrix, primaries and transfer when all three have the same number,
    # naming them by the matrix: the other two tables spell some numbers differently.
    if tags.get("color_primaries") == tags.get("colorspace") and "colorspace" in tags:
        same = {"smpte170m": ("smpte170m", "smpte170m"), "bt709": ("bt709", "bt709"),
                "bt470bg": ("bt470bg", "gamma28"), "smpte240m": ("smpte240m", "smpte240m"),
                "fcc": ("bt470m", "gamma22")}.get(tags["colorspace"])
        if same:
            tags["color_primaries"], tags["color_trc"] = same
    return tags


def colorspace_of(tags):
    """The swscale matrix for a stream's matrix tag (PyAV 10 has no BT.2020 one: BT.709's is used)."""
    reformatter = av().video.reformatter
    name = tags.get("colorspace", "bt709")
    if name in ("smpte170m", "bt470bg"):
        return reformatter.Colorspace.ITU601
    if name == "smpte240m":
        return reformatter.Colorspace.SMPTE240M
    if name == "fcc":
        return reformatter.Colorspace.FCC
    return reformatter.Colorspace.ITU709


class Family:
    """What a pixel format holds: 'yuv', 'rgb' or 'gray', its bits per sample, whether it has alpha."""

    def __init__(self, name):
        fmt = av().VideoFormat(name)
        components = fmt.components
        self.name = name
        self.bits = components[0].bits
        self.alpha = any(c.is_alpha for c in components)
        self.float = name.startswith(("grayf32", "gbrpf32", "gbrapf32"))
        if fmt.is_rgb:
            self.kind = "rgb"
        elif len(components) - self.alpha == 1:
            self.kind = "gray"
        else:
            self.kind = "yuv"
        self.full_range = name.startswith("yuvj")

    def planar(self):
        """The 4:4:4 planar format of the same family and depth (no matrix, no loss)."""
        if self.kind == "yuv":
            if self.bits == 8:
                return "yuvj444p" if self.full_range else "yuv444p"
            return f"yuv444p{min(max(self.bits, 9), 16)}le"
        if self.kind == "rgb":
            return "gbrp" if self.bits == 8 else f"gbrp{min(max(self.bits, 9), 16)}le"
        return "gray" if self.bits == 8 else "gray16le"


_SUBSAMPLING = {"420": (2, 2), "422": (1, 2), "444": (1, 1), "440": (2, 1), "411": (1, 4), "410": (4, 4)}


def chroma_factors(name):
    """(rows, columns) per chroma sample of a planar little-endian YUV format, or None."""
    match = re.fullmatch(r"yuvj?a?(4\d\d)p(\d+le)?", name)
    return _SUBSAMPLING.get(match.group(1)) if match else None


def upsample(chroma, factors, height, width):
    """Each chroma sample repeated over the pixels it covers (so that down(up(c)) is c exactly)."""
    rows, columns = factors
    return np.repeat(np.repeat(chroma, rows, axis=0), columns, axis=1)[:height, :width]


def downsample(samples, factors, height, width):
    """The mean of the pixels each chroma sample covers (edge pixels repeated for odd sizes),
    rounded; numpy's, so the same bits in every process (swscale's fast paths depend on the
    buffers' alignment)."""
    rows, columns = factors
    padded = np.pad(samples, ((0, height * rows - samples.shape[0]), (0, width * columns - samples.shape[1])),
                    mode="edge")
    blocks = padded.reshape(height, rows, width, columns)
    if samples.dtype == np.uint8:
        return ((blocks.sum(axis=(1, 3), dtype=np.uint32) + rows * columns // 2) // (rows * columns)).astype(np.uint8)
    return np.rint(blocks.mean(axis=(1, 3), dtype=np.float64))


def plane(frame, index, dtype):
    """A writable view of one plane of a planar frame, (height, width) samples."""
    p = frame.planes[index]
    dtype = np.dtype(dtype)
    flat = np.frombuffer(p, dtype)
    return flat.reshape(-1, p.line_size // dtype.itemsize)[:p.height, :p.width]


# ---- Sources --------------------------------------------------------------------------------------

class Source:
    """One input (colour or depth): its size, frame count, timestamps and format, probed once."""

    def __init__(self, role, path, fps):
        self.role, self.path = role, os.fspath(path)
        self.files = None
        if "%" in self.path:
            self.files = _pattern_files(role, self.path)
        elif os.path.isdir(self.path):
            self.files = sorted(os.path.join(self.path, f) for f in os.listdir(self.path)
                                if f.lower().endswith(IMAGE_EXTENSIONS) and not f.startswith("."))
            if not self.files:
                raise MediaError(f"{role} '{self.path}' is a directory without images ({', '.join(IMAGE_EXTENSIONS)})")
        elif not os.path.isfile(self.path):
            raise MediaError(f"{role} '{self.path}' does not exist")
        if self.files is not None:
            self._probe_images(fps)
        else:
            self._probe_video()

    def _probe_images(self, fps):
        self.kind = "images"
        self.count = len(self.files)
        self.rate = fractions.Fraction(fps if fps is not None else 25).limit_denominator(1001000)
        self.time_base = 1 / self.rate
        self.pts = np.arange(self.count, dtype=np.int64)
        self.tags = {}
        first = self.read_image(0)
        if isinstance(first, np.ndarray):
            self.height, self.width = first.shape[-2:]
            self.family = None  # EXR: float planes
        else:
            self.width, self.height = first.width, first.height
            self.family = Family(first.format.name)

    def _probe_video(self):
        self.kind = "video"
        module = av()
        try:
            container = module.open(self.path)
        except module.AVError as error:
            raise MediaError(f"{self.role} '{self.path}' cannot be opened: {error}") from None
        with container:
            if not container.streams.video:
                raise MediaError(f"{self.role} '{self.path}' has no video stream")
            stream = container.streams.video[0]
            self.index = stream.index
            self.time_base = stream.time_base
            self.rate = stream.average_rate or stream.guessed_rate
            context = stream.codec_context
            self.width, self.height = context.width, context.height
            if context.format is None:
                raise MediaError(f"{self.role} '{self.path}': its video stream has no pixel format")
            self.family = Family(context.format.name)
            self.tags = color_tags(container, stream.index)
            pts = []
            try:
                for packet in container.demux(stream):
                    if packet.size == 0:
                        continue
                    if packet.pts is None:
                        raise MediaError(f"{self.role} '{self.path}': frame {len(pts)} has no timestamp")
                    pts.append(packet.pts)
            except module.AVError as error:
                raise MediaError(f"{self.role} '{self.path}': cannot be read after frame {len(pts)}: {error}") from None
        self.pts = np.array(sorted(pts), dtype=np.int64)
        self.count = len(self.pts)
        if self.count == 0:
            raise MediaError(f"{self.role} '{self.path}' holds no frame")
        if np.any(np.diff(self.pts) == 0):
            raise MediaError(f"{self.role} '{self.path}': two frames share the timestamp "
                             f"{int(self.pts[np.flatnonzero(np.diff(self.pts) == 0)[0]])}")

    def seconds(self):
        return self.pts * float(self.time_base)

    def describe(self, index):
        if self.files is not None:
            return f"{self.role} '{self.files[index]}' (frame {index})"
        return f"{self.role} '{self.path}' frame {index}"

    def read_image(self, index):
        path = self.files[index]
        try:
            if path.lower().endswith(".exr"):
                return _exr.read(path, "color" if self.role == "colour" else "depth")
            module = av()
            with module.open(path) as container:
                for frame in container.decode(video=0):
                    return frame
        except (ValueError, OSError) as error:
            raise MediaError(f"{self.describe(index)}: {error}") from None
        except av().AVError as error:
            raise MediaError(f"{self.describe(index)} cannot be decoded: {error}") from None
        raise MediaError(f"{self.describe(index)} holds no picture")

    def frames(self, start, stop, pts=None):
        """Frames start..stop-1 in order: PyAV frames, or float arrays for EXR images. `pts`: the
        expected timestamps of a video's frames (the probe's, handed to a worker)."""
        if self.files is not None:
            for index in range(start, stop):
                frame = self.read_image(index)
                if getattr(frame, "width", None) not in (None, self.width) or getattr(frame, "height", self.height) \
                        != self.height or isinstance(frame, np.ndarray) and frame.shape[-2:] != (self.height, self.width):
                    size = frame.shape[-2:][::-1] if isinstance(frame, np.ndarray) else (frame.width, frame.height)
                    raise MediaError(f"{self.describe(index)} is {size[0]}x{size[1]}, the sequence "
                                     f"{self.width}x{self.height}")
                yield frame
            return
        expected = self.pts[start:stop] if pts is None else pts
        module = av()
        index = start
        try:
            with module.open(self.path) as container:
                stream = container.streams.video[0]
                stream.thread_type = "AUTO"
                if start > 0:
                    container.seek(int(expected[0]), stream=stream, backward=True)
                for frame in container.decode(stream):
                    if frame.pts is None or frame.pts < expected[0]:
                        continue
                    if frame.pts != expected[index - start]:
                        raise MediaError(f"{self.describe(index)} is missing or corrupt (the decoder gave the frame "
                                         f"at {frame.pts} for the one at {int(expected[index - start])})")
                    yield frame
                    index += 1
                    if index == stop:
                        return
        except module.AVError as error:
            raise MediaError(f"{self.describe(index)} cannot be decoded: {error}") from None
        raise MediaError(f"{self.describe(index)} is missing: the file ends before it (truncated?)")


def _pattern_files(role, pattern):
    try:
        pattern % 0
    except (TypeError, ValueError):
        raise MediaError(f"{role} '{pattern}' is not a printf pattern of one integer (e.g. frames/%04d.png)") from None
    folder, name = os.path.split(pattern)
    match = re.fullmatch(r"(.*)%(0?)(\d*)d(.*)", name)
    if not match or "%" in match.group(1) + match.group(4):
        raise MediaError(f"{role} '{pattern}': the file name must hold one %d or %0Nd")
    prefix, zero, digits, suffix = match.groups()
    number = r"\d+" if not digits else (rf"\d{{{digits},}}" if zero else r"\d+")
    found = {}
    regex = re.compile(re.escape(prefix) + f"({number})" + re.escape(suffix))
    for entry in os.listdir(folder or "."):
        hit = regex.fullmatch(entry)
        if hit and os.path.join(folder, entry) == pattern % int(hit.group(1)):
            found[int(hit.group(1))] = os.path.join(folder, entry)
    if not found:
        raise MediaError(f"{role} '{pattern}' matches no file")
    numbers = sorted(found)
    gaps = [n for n in range(numbers[0], numbers[-1] + 1) if n not in found]
    if gaps:
        raise MediaError(f"{role} '{pattern}' has no frame {gaps[0]} ('{pattern % gaps[0]}' is missing, "
                         f"between {numbers[0]} and {numbers[-1]})")
    return [found[n] for n in numbers]


# ---- Pixels ---------------------------------------------------------------------------------------

def depth_array(source, frame, index):
    """A depth frame as float32 (H, W) of its stored values (a 16-bit frame as integers, as a
    16-bit PNG), and the largest code of its format (1.0 for floats)."""
    if isinstance(frame, np.ndarray):
        return frame, 1.0
    family = Family(frame.format.name)
    if family.kind != "gray":
        raise MediaError(f"{source.describe(index)} is {frame.format.name}, not grey: depth must be one channel "
                         "(grey video or image: gray, gray16le, ...)")
    name = frame.format.name
    if family.float:
        dtype = ">f4" if name.endswith("be") else "<f4"
    elif family.bits > 8:
        dtype = ">u2" if name.endswith("be") else "<u2"
    else:
        dtype = np.uint8
    if family.alpha:  # ya8, ya16: grey and alpha interleaved in one plane
        samples = np.frombuffer(frame.planes[0], dtype).reshape(frame.height, -1)[:, 0:2 * frame.width:2]
    else:
        samples = plane(frame, 0, dtype)
    return samples.astype(np.float32), 1.0 if family.float else float((1 << family.bits) - 1)


def working_form(source, kind):
    """The working form of a colour source reprojected as `kind` ('yuv' or 'rgb'): (kind, bits,
    planar format). bits: 8 (uint8 (H, W, 4)), 9..16 (float32 planes of codes) or 32 (floats)."""
    family = source.family
    if family is None:
        return ("rgb", 32, "gbrpf32le")
    if family.bits <= 8:
        return (kind, 8, family.planar() if kind == "yuv" else "gbrp")
    if kind == "yuv" and family.kind == "yuv":
        return (kind, family.bits, family.planar())
    return ("rgb", 16, "gbrp16le")


def color_array(frame, working, colorspace):
    """A colour frame in the working form (module docstring; working_form)."""
    kind, bits, planar_format = working
    if isinstance(frame, np.ndarray):  # EXR planes, already float
        return frame if frame.shape[0] != 1 else np.repeat(frame, 3, axis=0)
    family = Family(frame.format.name)
    if family.kind == "gray":  # grey colour: the grey in R, G and B
        grey = frame.reformat(format="gray" if bits == 8 else "gray16le")
        samples = plane(grey, 0, np.uint8 if bits == 8 else "<u2")
        if bits == 8:
            out = np.empty((frame.height, frame.width, 4), np.uint8)
            out[..., :3] = samples[..., None]
            out[..., 3] = 255
            return out
        return np.repeat(samples[None].astype(np.float32), 3, axis=0)
    if kind == "yuv":
        factors = chroma_factors(frame.format.name)
        if factors is not None and (Family(frame.format.name).bits > 8) == (bits > 8):
            dtype = np.uint8 if bits == 8 else "<u2"
            luma = plane(frame, 0, dtype)
            chroma = [upsample(plane(frame, i, dtype), factors, frame.height, frame.width) for i in (1, 2)]
            if bits > 8:
                return np.stack([luma, *chroma]).astype(np.float32)
            out = np.empty((frame.height, frame.width, 4), np.uint8)
            out[..., 0], out[..., 1], out[..., 2], out[..., 3] = luma, chroma[0], chroma[1], 255
            return out
        planar = frame.reformat(format=planar_format)
        order = (0, 1, 2)
    else:
        planar = frame.reformat(format=planar_format, src_colorspace=colorspace, dst_colorspace=colorspace)
        order = (2, 0, 1)  # gbrp holds G, B, R
    if bits == 8:
        out = np.empty((frame.height, frame.width, 4), np.uint8)
        for channel, index in enumerate(order):
            out[..., channel] = plane(planar, index, np.uint8)
        out[..., 3] = 255
        return out
    return np.stack([plane(planar, index, "<u2").astype(np.float32) for index in order])


def to_video_frame(picture, working, out_format, colorspace):
    """The working form back to a frame of the output's pixel format."""
    module = av()
    kind, bits, planar_format = working
    factors = chroma_factors(out_format)
    if kind == "yuv" and factors is not None and (Family(out_format).bits > 8) == (bits > 8):
        height, width = picture.shape[:2] if bits == 8 else picture.shape[-2:]
        frame = module.VideoFrame(width, height, out_format)
        for p in frame.planes:  # the rows' padding too: an encoder may read it
            np.frombuffer(p, np.uint8)[...] = 0
        dtype = np.uint8 if bits == 8 else "<u2"
        top = (1 << Family(out_format).bits) - 1
        for index in range(3):
            samples = picture[..., index] if bits == 8 else picture[index]
            target = plane(frame, index, dtype)
            if index:
                samples = downsample(samples, factors, target.shape[0], target.shape[1])
            target[...] = samples if bits == 8 else np.clip(np.rint(samples), 0, top)
        return frame
    order = (0, 1, 2) if kind == "yuv" else (1, 2, 0)  # Y, U, V or G, B, R planes
    if bits == 8:
        height, width = picture.shape[:2]
        planar = module.VideoFrame(width, height, planar_format)
        for index, channel in enumerate(order):
            plane(planar, index, np.uint8)[...] = picture[..., channel]
    else:
        height, width = picture.shape[-2:]
        top = 65535 if bits == 32 else (1 << bits) - 1
        codes = np.clip(np.rint(picture[:3] * 65535.0 if bits == 32 else picture[:3]), 0, top)
        planar = module.VideoFrame(width, height, "gbrp16le" if bits == 32 else planar_format)
        for index, channel in enumerate(order):
            plane(planar, index, "<u2")[...] = codes[channel]
    if planar.format.name == out_format:
        return planar
    return planar.reformat(format=out_format, src_colorspace=colorspace, dst_colorspace=colorspace)


def to_image_frame(picture, working, extension):
    """The working form (RGB) as a frame for an image encoder: PNG 8 or 16 bits, EXR float."""
    module = av()
    _, bits, _ = working
    if extension == ".exr":
        values = picture[:3].astype(np.float32) if bits == 32 else (
            np.moveaxis(picture[..., :3], -1, 0).astype(np.float32) / 255.0 if bits == 8 else
            picture[:3] / float((1 << bits) - 1))
        frame = module.VideoFrame(values.shape[2], values.shape[1], "gbrpf32le")
        for index, channel in enumerate((1, 2, 0)):
            plane(frame, index, "<f4")[...] = values[channel]
        return frame
    if bits == 8:
        return module.VideoFrame.from_ndarray(np.ascontiguousarray(picture[..., :3]), format="rgb24")
    scale = 65535.0 if bits == 32 else 65535.0 / ((1 << bits) - 1)
    codes = np.clip(np.rint(np.moveaxis(picture[:3], 0, -1) * scale), 0, 65535).astype(np.uint16)
    return module.VideoFrame.from_ndarray(codes, format="rgb48le").reformat(format="rgb48be")
