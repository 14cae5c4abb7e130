#!/usr/bin/env python3
"""Writes the seed corpora of the file-reader harnesses (fuzz/corpus/{png,pfm,exr}/): small valid
files of every form each reader handles, and a few broken ones next to them, so that a fuzzing
run starts from deep inside each format instead of having to discover its signature and header;
the named inputs of the CLI and warp harnesses; and fuzz_formats' inputs (fuzz/corpus/formats/):
every colour format x depth format as a valid frame, and one input per fault the harness injects.
Standard library only; deterministic (re-running it rewrites the same bytes).

    python3 fuzz/make_seeds.py            # from the repository root
"""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(harness, name, data):
    directory = os.path.join(HERE, "corpus", harness)
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, name), "wb") as f:
        f.write(data)


# ---- PNG -------------------------------------------------------------------------------------

def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


def png(width, height, bit_depth, color_type, rows, interlace=0, extra=b""):
    """rows: the filtered scanline bytes (each starting with its filter byte), already laid out."""
    header = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, interlace)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + extra + chunk(b"IDAT", zlib.compress(rows)) +
            chunk(b"IEND", b""))


def raw_rows(width, height, bytes_per_pixel, value):
    out = b""
    for y in range(height):
        out += b"\x00" + bytes(value(x, y, i) & 0xFF for x in range(width) for i in range(bytes_per_pixel))
    return out


def png_seeds():
    write("png", "grey8_3x2.png", png(3, 2, 8, 0, raw_rows(3, 2, 1, lambda x, y, i: 40 * x + 90 * y)))
    write("png", "grey16_2x2.png", png(2, 2, 16, 0, raw_rows(2, 2, 2, lambda x, y, i: 0x12 * (x + 1) + 0x40 * y + i)))
    write("png", "grey1_9x2.png", png(9, 2, 1, 0, b"\x00\xa5\x80\x00\x5a\x00"))
    write("png", "grey_alpha8_2x2.png", png(2, 2, 8, 4, raw_rows(2, 2, 2, lambda x, y, i: 100 * i + x + 7 * y)))
    write("png", "rgb8_3x3.png", png(3, 3, 8, 2, raw_rows(3, 3, 3, lambda x, y, i: 30 * x + 50 * y + 80 * i)))
    write("png", "rgba16_2x1.png", png(2, 1, 16, 6, raw_rows(2, 1, 8, lambda x, y, i: 31 * i + x)))
    palette = chunk(b"PLTE", bytes([255, 0, 0, 0, 255, 0, 0, 0, 255]))
    trns = chunk(b"tRNS", bytes([255, 128]))
    write("png", "palette_trns_3x2.png",
          png(3, 2, 8, 3, raw_rows(3, 2, 1, lambda x, y, i: (x + y) % 3), extra=palette + trns))
    write("png", "rgb_colour_key_2x2.png",
          png(2, 2, 8, 2, raw_rows(2, 2, 3, lambda x, y, i: 255 * ((x + y) % 2)), extra=chunk(b"tRNS", b"\x00\xff\x00\xff\x00\xff")))
    # Adam7-interlaced 3x3 grey.
    write("png", "interlaced_grey8_3x3.png", png(3, 3, 8, 0, adam7_rows(3, 3), interlace=1))
    # Broken: a CRC error, and a file cut in its IDAT.
    good = png(3, 3, 8, 2, raw_rows(3, 3, 3, lambda x, y, i: x * y * i))
    write("png", "bad_crc.png", good[:-5] + bytes([good[-5] ^ 0xFF]) + good[-4:])
    write("png", "truncated.png", good[: len(good) // 2 + 10])


def adam7_rows(width, height):
    starts = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]
    out = b""
    for x0, y0, dx, dy in starts:
        columns = len(range(x0, width, dx))
        for y in range(y0, height, dy):
            if columns == 0:
                continue
            out += b"\x00" + bytes((17 * x + 29 * y) & 0xFF for x in range(x0, width, dx))
    return out


# ---- PFM -------------------------------------------------------------------------------------

def pfm(kind, width, height, scale, values, order):
    header = b"%s\n%d %d\n%s\n" % (kind, width, height, scale)
    return header + b"".join(struct.pack(order + "f", v) for v in values)


def pfm_seeds():
    nan, inf = float("nan"), float("inf")
    write("pfm", "grey_le_3x2.pfm", pfm(b"Pf", 3, 2, b"-1.0", [0.5, 1.0, 2.0, nan, -inf, 1e-40], "<"))
    write("pfm", "grey_be_2x2.pfm", pfm(b"Pf", 2, 2, b"1.0", [1.0, 2.0, 3.0, 4.0], ">"))
    write("pfm", "rgb_le_2x1.pfm", pfm(b"PF", 2, 1, b"-1", [0.1, 0.2, 0.3, 0.4, 0.5, 0.6], "<"))
    write("pfm", "rgb_be_1x2.pfm", pfm(b"PF", 1, 2, b"2.5", [1, 2, 3, 4, 5, 6], ">"))
    write("pfm", "crlf_header.pfm", b"Pf\r\n1 1\r\n-1.0\n" + struct.pack("<f", 7.0))
    write("pfm", "truncated.pfm", pfm(b"Pf", 4, 4, b"-1.0", [1.0] * 5, "<"))
    write("pfm", "bad_header.pfm", b"Pf\n-3 x\n-1.0\n")


# ---- OpenEXR (single-part scanline, uncompressed or ZIP; written by hand) -------------------

def attribute(name, kind, body):
    return name + b"\x00" + kind + b"\x00" + struct.pack("<i", len(body)) + body


def exr(width, height, channels, compression=0, tiled=False):
    """channels: [(name, pixel_type)] sorted by name; pixel_type 1 half, 2 float. Pixel values are
    small ramps. compression 0: none, 2: ZIPS (one line per block)."""
    channel_list = b"".join(name + b"\x00" + struct.pack("<iB3xii", ptype, 0, 1, 1) for name, ptype in channels) + b"\x00"
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (struct.pack("<ii", 20000630, 2) +
              attribute(b"channels", b"chlist", channel_list) +
              attribute(b"compression", b"compression", bytes([compression])) +
              attribute(b"dataWindow", b"box2i", box) +
              attribute(b"displayWindow", b"box2i", box) +
              attribute(b"lineOrder", b"lineOrder", b"\x00") +
              attribute(b"pixelAspectRatio", b"float", struct.pack("<f", 1.0)) +
              attribute(b"screenWindowCenter", b"v2f", struct.pack("<ff", 0.0, 0.0)) +
              attribute(b"screenWindowWidth", b"float", struct.pack("<f", 1.0)) + b"\x00")
    blocks = []
    for y in range(height):
        line = b""
        for c, (name, ptype) in enumerate(channels):
            for x in range(width):
                value = 0.25 * (x + 1) + 0.5 * y + c
                line += struct.pack("<e", value) if ptype == 1 else struct.pack("<f", value)
        if compression == 2:
            packed = zip_predict(line)
            if len(packed) < len(line):  # else the block is stored as it is (the format's rule)
                line = packed
        blocks.append(struct.pack("<ii", y, len(line)) + line)
    offset = len(header) + 8 * height
    table = b""
    for block in blocks:
        table += struct.pack("<Q", offset)
        offset += len(block)
    return header + table + b"".join(blocks)


def zip_predict(data):
    """OpenEXR's ZIP: bytes split into even/odd halves, delta-coded, then zlib."""
    half = (len(data) + 1) // 2
    reordered = bytearray(len(data))
    reordered[:half] = data[0::2]
    reordered[half:] = data[1::2]
    out = bytearray(len(data))
    previous = reordered[0] if data else 0
    if data:
        out[0] = reordered[0]
    for i in range(1, len(reordered)):
        out[i] = (reordered[i] - previous + 128 + 256) & 0xFF
        previous = reordered[i]
    return zlib.compress(bytes(out))


def exr_seeds():
    write("exr", "rgb_half_2x2.exr", exr(2, 2, [(b"B", 1), (b"G", 1), (b"R", 1)]))
    write("exr", "rgbaz_float_3x2.exr", exr(3, 2, [(b"A", 2), (b"B", 2), (b"G", 2), (b"R", 2), (b"Z", 2)]))
    write("exr", "z_only_2x3.exr", exr(2, 3, [(b"Z", 2)]))
    write("exr", "blender_layers_2x2.exr",
          exr(2, 2, [(b"ViewLayer.Combined.B", 1), (b"ViewLayer.Combined.G", 1), (b"ViewLayer.Combined.R", 1),
                     (b"ViewLayer.Depth.Z", 2)]))
    write("exr", "grey_y_zips_40x2.exr", exr(40, 2, [(b"Y", 1)], compression=2))
    write("exr", "depth_named_2x1.exr", exr(2, 1, [(b"depth", 2)]))
    good = exr(2, 2, [(b"B", 1), (b"G", 1), (b"R", 1)])
    write("exr", "truncated.exr", good[: len(good) - 6])


# ---- A whole warp: colour and depth files together (fuzz_warp.cpp's layout) ------------------

def warp_input(color_format, depth_format, method, camera, color, depth):
    """formats: 0 PNG, 1 PFM, 2 EXR; method 0..4; camera 0 linear, 1 standard, 2 disparity."""
    return bytes([color_format + 3 * depth_format, method + 5 * camera]) + struct.pack("<H", len(color)) + color + depth


def warp_seeds():
    ramp = lambda x, y, i: 30 * x + 50 * y + 80 * i
    rgb_png = png(4, 2, 8, 2, raw_rows(4, 2, 3, ramp))
    grey16_png = png(4, 2, 16, 0, raw_rows(4, 2, 2, lambda x, y, i: (x + 1) * 3 if i else 0))
    depth_pfm = pfm(b"Pf", 4, 2, b"-1.0", [1.0, 2.0, 4.0, float("nan"), 8.0, 3.0, 2.0, 1.5], "<")
    rgb_pfm = pfm(b"PF", 4, 2, b"-1.0", [0.1 * i for i in range(24)], "<")
    write("warp", "png_pfm_linear", warp_input(0, 1, 0, 0, rgb_png, depth_pfm))
    write("warp", "pfm_png_disparity", warp_input(1, 0, 2, 2, rgb_pfm, grey16_png))
    write("warp", "exr_exr_standard", warp_input(2, 2, 4, 1, exr(3, 2, [(b"B", 1), (b"G", 1), (b"R", 1)]),
                                                 exr(3, 2, [(b"Z", 2)])))
    write("warp", "exr_with_z_pfm_secant", warp_input(2, 1, 4, 0, exr(3, 2, [(b"A", 2), (b"B", 2), (b"G", 2), (b"R", 2), (b"Z", 2)]),
                                                      pfm(b"Pf", 3, 2, b"1.0", [5.0] * 6, ">")))
    write("warp", "sizes_differ", warp_input(0, 1, 1, 0, rgb_png, pfm(b"Pf", 2, 2, b"-1.0", [1.0] * 4, "<")))
    write("warp", "depth_truncated", warp_input(0, 1, 3, 1, rgb_png, depth_pfm[:-5]))


# ---- CLI arguments (NUL-separated, after "reproject warp") --------------------------------------

def cli_seeds():
    lists = {
        "standard_secant": ["--color", "c.png", "--depth", "d.pfm", "--encoding", "standard", "--near", "0.1",
                            "--far", "100", "--convergence", "2", "--method", "secant", "--threads", "2",
                            "--arch", "avx2", "--out", "r.png"],
        "equals_form": ["--encoding=reversed_infinite", "--near=0.5", "--convergence=3.5", "--separation=0.05",
                        "--direction=right-to-left", "--guard=4", "--fill=foreground", "--edge=none"],
        "disparity": ["--disparity", "--direction", "left-to-right", "--method", "march16", "--march-steps", "32",
                      "--max-negative-parallax", "12.5", "--hole-threshold", "0.5"],
        "linear_single": ["--encoding", "linear", "--convergence", "1e3", "--method", "single", "--probe-parallax",
                          "-7", "--secant-max-steps", "4096", "--methods", "exact,secant,scanline"],
        "errors": ["--near", "x", "--near", "1", "--bogus", "--quiet=1", "loose", "--far"],
        "help": ["--help"],
    }
    for name, words in lists.items():
        write("cli", name, b"\x00".join(w.encode() for w in words))


# ---- fuzz_formats: the harness's choices, encoded as FuzzedDataProvider reads them ---------------

class Provider:
    """Mirrors FuzzedDataProvider for the calls fuzz_formats.cpp makes, in its order: integers are
    read from the end of the input (the byte read first is the last one of the file, most
    significant first), the pixel bytes are the rest, from the start."""

    def __init__(self):
        self.consumed = []

    def range(self, low, high, value):
        assert low <= value <= high, (low, high, value)
        span, offset, n = high - low, 0, 0
        while offset < 32 and (span >> offset) > 0:
            n += 1
            offset += 8
        x = value - low
        self.consumed += [(x >> (8 * (n - 1 - i))) & 0xFF for i in range(n)]

    def boolean(self, value):
        self.consumed.append(1 if value else 0)

    def input(self, pixels):
        return bytes(pixels) + bytes(reversed(self.consumed))


COLOR_KINDS = {"rgba8": 0, "rgba8_srgb": 2, "rgba16f": 4, "float_rgba": 6, "float_planar": 7}
DEPTH_KINDS = {"float_plane": 0, "float32": 1, "unorm16": 2, "unorm24_s8": 4, "s8_unorm24": 6, "packed_linear": 8}
FAULTS = ["none", "target_color_format", "source_color_unknown", "target_color_unknown", "source_depth_unknown",
          "target_depth_format", "source_both_depths", "target_both_depths", "target_float_depth", "stride_too_small",
          "float_depth_misaligned", "packed_range", "size_off", "null_data", "color_shape", "guard_too_wide",
          "bad_option", "color_layout_unknown", "aliasing"]


def formats_input(color, depth, width, height, method, guard=0, api=0, color_mode=0, depth_mode=2, fault="none",
                  variant=0, pad=3, offset=1, threads=1, edge=0, hole_fill=0, convergence=2, seed=0):
    """One frame: a standard decoder (near 1, far 100; linear for packed depth), a stereo model
    (separation 0.03, convergence 2 or 10, left to right), every output present."""
    p = Provider()
    small = width <= 40
    p.boolean(small)
    p.range(0, 40 if small else 300, width)
    p.range(0, 8, height)
    kind = COLOR_KINDS[color]
    p.range(0, 7, kind)
    if kind == 7:
        p.range(1, 4, 3)
    float_color = kind >= 6
    p.range(0, 3 if float_color else 9, pad % 4 if float_color else pad)  # source colour pad
    p.range(0, 7, offset)                                                     # its base offset
    dkind = DEPTH_KINDS[depth]
    p.range(0, 9, dkind)
    float_depth = dkind <= 1
    p.range(0, 3 if float_depth else 9, pad % 4 if float_depth else pad)
    p.range(0, 7, offset + 2)
    if depth == "packed_linear":
        p.range(0, 8, 1)  # range 0.5 .. 40
    p.range(0, 3 if float_color else 9, (pad + 1) % 4 if float_color else (pad + 1) % 10)  # target colour
    p.range(0, 7, offset + 1)
    p.boolean(True)  # output depth
    if float_depth:
        p.range(0, 3, 1)  # same kind as the source
    p.range(0, 3 if float_depth else 9, (pad + 2) % 4 if float_depth else (pad + 2) % 10)
    p.range(0, 7, offset + 3)
    p.range(0, 3, 1)  # the output's range fields: the source's
    p.range(0, 3, 1)  # status
    p.boolean(True)   # source_x
    p.range(0, 9, pad)
    p.range(0, 3, 1)
    p.range(0, 3, api)
    p.range(0, 2, color_mode)
    p.range(0, 2, depth_mode)
    if depth == "packed_linear":
        p.range(0, 7, 0)  # linear
    else:
        p.range(0, 7, 2)  # from_near_far
        p.range(0, 7, 1)  # standard
        p.range(0, 5, 2)  # near 1
        p.range(0, 5, 2)  # far 100 near
    p.range(0, 4, 0)      # left to right
    p.range(0, 3, 0)      # stereo
    p.range(0, 5, 2)      # separation 0.03
    p.range(0, 5, {2: 2, 10: 3}[convergence])
    p.range(0, 4, method)
    p.range(0, 2, hole_fill)
    p.range(0, 3, edge)
    p.range(0, 4, 0)      # hole threshold 1
    p.boolean(False)      # max_negative_parallax: the frame's
    p.boolean(False)      # probe_parallax
    p.boolean(False)      # march_steps
    p.boolean(False)      # secant_max_steps
    p.boolean(False)      # arch: the selected one
    p.boolean(threads == 2)
    p.boolean(guard == 0)
    if guard:
        p.range(0, max(0, (width - 1) // 2), guard)
    count = len(FAULTS)
    p.range(0, 2 * count - 2, 0 if fault == "none" else FAULTS.index(fault) + count - 1)
    p.range(0, 59, variant)
    state = 0x9E3779B9 ^ (seed * 0x85EBCA6B) & 0xFFFFFFFF  # xorshift32: the same bytes on any Python
    pixels = []
    for _ in range(640):
        state ^= (state << 13) & 0xFFFFFFFF
        state ^= state >> 17
        state ^= (state << 5) & 0xFFFFFFFF
        pixels.append(state & 0xFF)
    return p.input(pixels)


def formats_seeds():
    methods = ["scanline", "march16", "single", "secant", "exact"]
    n = 0
    for color in COLOR_KINDS:
        for depth in DEPTH_KINDS:
            method = n % 5
            width = [64, 97, 130, 33, 150][n % 5]
            write("formats", "%s+%s_%s" % (color, depth, methods[method]),
                  formats_input(color, depth, width, 3 + n % 3, method, guard=n % 3 * 2, api=n % 4,
                                color_mode=n % 3 if color.startswith("float") or color == "rgba16f" else 0,
                                depth_mode=2 if n % 4 else 1, edge=n % 4, hole_fill=n % 3, threads=1 + n % 2,
                                pad=n % 10, offset=n % 5, convergence=10 if n % 2 else 2, seed=n))
            n += 1
    for i, fault in enumerate(FAULTS[1:]):
        color = list(COLOR_KINDS)[i % 5]
        depth = {"float_depth_misaligned": "float32", "packed_range": "packed_linear", "target_float_depth": "unorm16",
                 "source_depth_unknown": "s8_unorm24"}.get(fault, list(DEPTH_KINDS)[i % 6])
        write("formats", "fault_" + fault, formats_input(color, depth, 24, 2, i % 5, fault=fault, variant=i % 2,
                                                         pad=i % 10, seed=100 + i))


if __name__ == "__main__":
    formats_seeds()
    cli_seeds()
    png_seeds()
    pfm_seeds()
    exr_seeds()
    warp_seeds()
