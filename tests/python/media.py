# Small test media for the video tests, made with PyAV: colour and depth videos of a textured
# frontal plane sliding sideways, with optional audio, subtitles, variable timestamps and colour tags.
import fractions

import av
import numpy as np


def texture(width, height, k, bits=8):
    """A frame of a texture with structure in both directions, moving 1 px a frame."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    x = x + k
    top = (1 << bits) - 1
    planes = [0.5 + 0.4 * np.sin(x * 0.37) * np.cos(y * 0.23), 0.5 + 0.4 * np.sin((x + y) * 0.11),
              0.5 + 0.4 * np.cos(x * 0.05 - y * 0.31)]
    return np.stack([np.rint(p * top) for p in planes], axis=-1).astype(np.uint8 if bits == 8 else np.uint16)


def depth_codes(width, height, k, near=2.0, far=9.0):
    """Linear depth in millimetres: a slanted plane and a nearer box that moves."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    z = near + (far - near) * x / max(width - 1, 1)
    box = (abs(x - (width * 0.3 + k) % width) < width * 0.15) & (abs(y - height / 2) < height * 0.25)
    z[box] = near * 0.9
    return np.rint(z * 1000).astype(np.uint16)


def write_video(path, frames, pix_fmt, *, codec="ffv1", source_format="rgb24", rate=24, pts=None, time_base=None,
                options=None, audio=False, subtitles=False, planar=False):
    """Writes `frames` (arrays in `source_format`) with the given timestamps; audio: a FLAC sine,
    subtitles: two SubRip cues (Matroska)."""
    out = av.open(str(path), "w")
    stream = out.add_stream(codec, rate=rate)
    stream.width, stream.height, stream.pix_fmt = frames[0].shape[1], frames[0].shape[0], pix_fmt
    if time_base is not None:
        stream.codec_context.time_base = time_base
    stream.options = dict(options or {})
    audio_stream = None
    if audio:
        audio_stream = out.add_stream("flac", rate=8000)
        audio_stream.layout = "mono"
    if subtitles:
        out.add_stream("subrip")
    for i, array in enumerate(frames):
        frame = av.VideoFrame.from_ndarray(array, format=source_format)
        if frame.format.name != pix_fmt:
            frame = frame.reformat(format=pix_fmt)
        frame.pts = i if pts is None else pts[i]
        if time_base is not None:
            frame.time_base = time_base
        for packet in stream.encode(frame):
            out.mux(packet)
    for packet in stream.encode(None):
        out.mux(packet)
    if audio_stream is not None:
        seconds = len(frames) / float(rate)
        samples = (np.sin(np.arange(int(8000 * seconds)) * 0.05) * 8000).astype(np.int16)
        for start in range(0, samples.size, 1024):
            chunk = av.AudioFrame.from_ndarray(samples[None, start:start + 1024], format="s16", layout="mono")
            chunk.sample_rate, chunk.pts = 8000, start
            for packet in audio_stream.encode(chunk):
                out.mux(packet)
        for packet in audio_stream.encode(None):
            out.mux(packet)
    out.close()


def decoded(path, fmt=None):
    with av.open(str(path)) as container:
        return [(f.pts, f.to_ndarray(format=fmt) if fmt else f) for f in container.decode(video=0)]


def frame_times(path):
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        return [float(f.pts * stream.time_base) for f in container.decode(stream)]
