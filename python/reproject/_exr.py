"""A small OpenEXR reader for image sequences (reproject.video): FFmpeg decodes no depth channel,
and an engine's or Blender's frame dumps keep depth in Z.

Scanline, single-part files; compression NONE, RLE, ZIPS or ZIP (OpenEXR's and Blender's default);
HALF, FLOAT and UINT channels, not subsampled. Anything else raises ValueError naming the file and
what it holds. Channels are chosen by the rule of the C++ tool's reader (tools/imageio, docs/CLI.md
"Files"): colour is the top-level R, G, B (+ A), else one layer's (Blender's ViewLayer.Combined
when there are several), else Y; depth is Z, else a channel named depth, else one layer's Z or
depth (not a vector's Z beside X or Y, nor Blender's Mist).
"""
import struct
import zlib

import numpy as np

_COMPRESSION = ("none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab")
_LINES = {0: 1, 1: 1, 2: 1, 3: 16}
_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


class _Header:
    def __init__(self, path, data):
        if data[:4] != b"\x76\x2f\x31\x01":
            raise ValueError(f"'{path}' is not an OpenEXR file")
        flags = struct.unpack_from("<I", data, 4)[0]
        if flags & (0x200 | 0x800 | 0x1000):  # tiled, deep, multi-part
            raise ValueError(f"'{path}': tiled or multi-part OpenEXR files are not read here (save scanline images)")
        pos, self.channels, self.compression, self.window = 8, [], None, None
        while True:
            end = data.index(b"\0", pos)
            name = data[pos:end].decode("latin-1")
            if not name:
                pos = end + 1
                break
            type_end = data.index(b"\0", end + 1)
            kind = data[end + 1:type_end].decode("latin-1")
            size = struct.unpack_from("<i", data, type_end + 1)[0]
            value = data[type_end + 5:type_end + 5 + size]
            if len(value) != size:
                raise ValueError(f"'{path}' is truncated (in its header)")
            if name == "channels" and kind == "chlist":
                self._read_channels(path, value)
            elif name == "compression":
                self.compression = value[0]
            elif name == "dataWindow":
                self.window = struct.unpack("<4i", value)
            elif name == "type" and (b"tiled" in value or b"deep" in value):
                raise ValueError(f"'{path}': tiled or deep OpenEXR files are not read here")
            pos = type_end + 5 + size
        if self.window is None or not self.channels or self.compression is None:
            raise ValueError(f"'{path}': an OpenEXR header without channels, compression or data window")
        if self.compression not in _LINES:
            name = _COMPRESSION[self.compression] if self.compression < len(_COMPRESSION) else str(self.compression)
            raise ValueError(f"'{path}': OpenEXR compression {name} is not read here (NONE, RLE, ZIPS and ZIP are; "
                             "save the frames with ZIP)")
        self.offsets_at = pos

    def _read_channels(self, path, value):
        pos = 0
        while pos < len(value) and value[pos] != 0:
            end = value.index(b"\0", pos)
            name = value[pos:end].decode("latin-1")
            pixel_type, _, x_sampling, y_sampling = struct.unpack_from("<iB3xii", value, end + 1)
            if pixel_type not in _TYPES:
                raise ValueError(f"'{path}': channel '{name}' has an unknown pixel type {pixel_type}")
            if x_sampling != 1 or y_sampling != 1:
                raise ValueError(f"'{path}': channel '{name}' is subsampled ({x_sampling}x{y_sampling})")
            self.channels.append((name, _TYPES[pixel_type]))
            pos = end + 1 + 16
        self.channels.sort()


def _undo_zip(raw, expected):
    data = np.frombuffer(raw, np.uint8).astype(np.int32) - 128
    if data.size != expected:
        raise ValueError("a chunk inflates to the wrong size")
    data[0] += 128
    predicted = (np.cumsum(data) & 0xFF).astype(np.uint8)
    out = np.empty(expected, np.uint8)
    half = (expected + 1) // 2
    out[0::2] = predicted[:half]
    out[1::2] = predicted[half:]
    return out


def _unrle(raw):
    out, pos = bytearray(), 0
    while pos < len(raw):
        count = struct.unpack_from("b", raw, pos)[0]
        pos += 1
        if count < 0:
            out += raw[pos:pos - count]
            pos -= count
        else:
            out += raw[pos:pos + 1] * (count + 1)
            pos += 1
    return bytes(out)


def _layer(name):
    return name.rpartition(".")[0]


def _last(name):
    return name.rpartition(".")[2]


def _color_names(names, layer):
    def joined(c):
        return f"{layer}.{c}" if layer else c
    if all(joined(c) in names for c in "RGB"):
        chosen = [joined(c) for c in "RGB"]
    elif joined("Y") in names:
        chosen = [joined("Y")]
    else:
        return []
    return chosen + ([joined("A")] if joined("A") in names else [])


def choose_color(path, names):
    if all(c in names for c in "RGB"):
        return _color_names(names, "")
    layers = sorted({_layer(n) for n in names if _layer(n) and _last(n) == "R"
                     and f"{_layer(n)}.G" in names and f"{_layer(n)}.B" in names})
    if len(layers) > 1:
        combined = [layer for layer in layers if _last(layer) == "Combined"]
        if len(combined) != 1:
            raise ValueError(f"'{path}': several colour layers ({', '.join(layers)}) and no single 'Combined' one")
        layers = combined
    if layers:
        return _color_names(names, layers[0])
    if "Y" in names:
        return _color_names(names, "")
    raise ValueError(f"'{path}': no colour channels (R, G, B or Y); channels: {', '.join(sorted(names))}")


def choose_depth(path, names):
    if "Z" in names:
        return "Z"
    top, depth_layer, other = [], [], []
    for name in sorted(names):
        last, layer = _last(name), _layer(name)
        if last != "Z" and last.lower() != "depth":
            continue
        if not layer:
            top.append(name)
        elif f"{layer}.X" in names or f"{layer}.Y" in names:
            continue
        elif _last(layer).lower() == "depth":
            depth_layer.append(name)
        elif _last(layer).lower() != "mist":
            other.append(name)
    for step in (top, depth_layer, other):
        if len(step) > 1:
            raise ValueError(f"'{path}': several depth channels ({', '.join(step)})")
        if step:
            return step[0]
    raise ValueError(f"'{path}': no depth channel (Z or depth); channels: {', '.join(sorted(names))}")


def read(path, purpose):
    """The colour planes (C, H, W) or the depth (H, W) of an OpenEXR file, float32."""
    with open(path, "rb") as f:
        data = f.read()
    header = _Header(path, data)
    xmin, ymin, xmax, ymax = header.window
    width, height = xmax - xmin + 1, ymax - ymin + 1
    if width < 1 or height < 1 or width * height > 1 << 28:
        raise ValueError(f"'{path}': data window {width}x{height} is empty or too large")
    names = {n for n, _ in header.channels}
    wanted = choose_color(path, names) if purpose == "color" else [choose_depth(path, names)]
    lines = _LINES[header.compression]
    blocks = (height + lines - 1) // lines
    offsets = np.frombuffer(data, "<u8", blocks, header.offsets_at)
    line_bytes = sum(width * dtype.itemsize for _, dtype in header.channels)
    planes = {name: np.empty((height, width), np.float32) for name in wanted}
    for offset in offsets:
        if offset + 8 > len(data):
            raise ValueError(f"'{path}' is truncated: a chunk starts at byte {offset} of {len(data)}")
        y, size = struct.unpack_from("<ii", data, int(offset))
        raw = data[int(offset) + 8:int(offset) + 8 + size]
        first = y - ymin
        count = min(lines, height - first)
        if len(raw) != size or first < 0 or count < 1:
            raise ValueError(f"'{path}' is truncated or corrupt (the chunk of line {y})")
        expected = count * line_bytes
        try:
            if size == expected:
                block = np.frombuffer(raw, np.uint8)
            elif header.compression in (2, 3):
                block = _undo_zip(zlib.decompress(raw), expected)
            elif header.compression == 1:
                block = _undo_zip(_unrle(raw), expected)
            else:
                raise ValueError("a chunk of the wrong size")
        except (zlib.error, ValueError, IndexError, struct.error) as error:
            raise ValueError(f"'{path}' is corrupt (the chunk of line {y}: {error})") from None
        rows = block.reshape(count, line_bytes)
        start = 0
        for name, dtype in header.channels:
            stop = start + width * dtype.itemsize
            if name in planes:
                planes[name][first:first + count] = rows[:, start:stop].copy().view(dtype)
            start = stop
    if purpose == "color":
        return np.stack([planes[name] for name in wanted])
    return planes[wanted[0]]
