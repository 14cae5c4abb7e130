# reproject.video: whole sequences and videos (PyAV). Every converted frame is checked against the
# library's own warp of the decoded inputs or against the ray-cast truth; audio packets, timestamps
# and colour tags against the input's; bad input against its message and the folder it leaves.
import fractions
import inspect
import os
import pathlib
import pickle
import re
import subprocess
import sys

import numpy as np
import pytest

av = pytest.importorskip("av", reason="PyAV is not installed (Debian: python3-av)")

import media  # noqa: E402
import pfm  # noqa: E402
import reproject  # noqa: E402
import reproject.metrics  # noqa: E402
import reproject.video  # noqa: E402
from reproject.video import ConvertError, convert  # noqa: E402

W, H, N = 96, 64, 20
CAMERA = dict(encoding="linear", depth_scale=0.001, convergence=4.0)


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    """A colour video (x264, with FLAC audio), its colour as lossless RGB (FFV1), and its depth in
    millimetres (FFV1 16-bit grey)."""
    folder = tmp_path_factory.mktemp("clip")
    colors = [media.texture(W, H, k) for k in range(N)]
    media.write_video(folder / "colour.mkv", colors, "yuv420p", codec="libx264", audio=True)
    media.write_video(folder / "rgb.mkv", colors, "bgr0")
    media.write_video(folder / "depth.mkv", [media.depth_codes(W, H, k) for k in range(N)], "gray16le",
                      source_format="gray16le")
    return folder


def listing(folder):
    return sorted(str(p.relative_to(folder)) for p in pathlib.Path(folder).rglob("*"))


def warp_pair_of(color, depth_mm):
    decoder = reproject.Decoder()
    model = reproject.StereoCamera(0.03, 4.0).parallax(color.shape[1], "centre-to-right")
    rgba = np.dstack([color, np.full(color.shape[:2], 255, np.uint8)])
    pair = reproject.warp_pair(rgba, depth_mm.astype(np.float32) * np.float32(0.001), decoder=decoder, model=model)
    return pair.left.color[..., :3], pair.right.color[..., :3]


# ---- Frames ---------------------------------------------------------------------------------------

def test_every_frame_is_the_librarys_pair_of_the_decoded_inputs(clip, tmp_path):
    out = tmp_path / "sbs.mkv"
    calls = []
    assert convert(clip / "rgb.mkv", clip / "depth.mkv", out, codec="ffv1", segment_frames=6,
                   progress=lambda done, total: calls.append((done, total)), **CAMERA) == [str(out)]
    assert calls == [(k, N) for k in range(1, N + 1)]
    colors = media.decoded(clip / "rgb.mkv", "rgb24")
    depths = media.decoded(clip / "depth.mkv", "gray16le")
    frames = media.decoded(out, "rgb24")
    assert len(frames) == N
    for (_, color), (_, depth), (_, sbs) in zip(colors, depths, frames):
        left, right = warp_pair_of(color, depth)
        assert sbs.shape == (H, 2 * W, 3)
        assert np.array_equal(sbs[:, :W], left) and np.array_equal(sbs[:, W:], right)
    assert not any("reproject" in name for name in os.listdir(tmp_path))  # parts and temporaries gone


def test_the_progress_bar_shows_frames_per_second(clip, tmp_path, capsys):
    convert(clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "bar.mkv", codec="ffv1", quiet=False, **CAMERA)
    bar = capsys.readouterr().err
    assert f"100%" in bar and f"{N}/{N}" in bar and "frame/s" in bar


def test_layouts_and_their_suffixes(clip, tmp_path):
    separate = convert(clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "eye.mkv", codec="ffv1", layout="separate",
                       **CAMERA)
    assert separate == [str(tmp_path / "eye_L.mkv"), str(tmp_path / "eye_R.mkv")]
    left = media.decoded(separate[0], "rgb24")[3][1].astype(np.int32)
    right = media.decoded(separate[1], "rgb24")[3][1].astype(np.int32)
    half_l, half_r = (left[:, 0::2] + left[:, 1::2] + 1) >> 1, (right[:, 0::2] + right[:, 1::2] + 1) >> 1
    expected = {"sbsr": np.hstack([right, left]), "abl": np.vstack([left, right]), "ab2r": None,
                "sbs2l": np.hstack([half_l, half_r])}
    for layout, picture in expected.items():
        out = convert(clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "x.mkv", codec="ffv1", layout=layout,
                      suffix=True, **CAMERA)[0]
        assert out.endswith(reproject.video._SUFFIX[layout] + ".mkv")
        frame = media.decoded(out, "rgb24")[3][1]
        if picture is not None:
            assert np.array_equal(frame, picture), layout
        else:
            assert frame.shape == (H, W, 3)
        with av.open(out) as container:
            assert container.streams.video[0].metadata["stereo_mode"] == reproject.video._STEREO_MODE[layout]
    anaglyph = convert(clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "a.mkv", codec="ffv1", layout="anaglyph",
                       **CAMERA)[0]
    mixed = left @ reproject.video._DUBOIS_LEFT.T.astype(np.float64) + right @ reproject.video._DUBOIS_RIGHT.T
    assert np.abs(media.decoded(anaglyph, "rgb24")[3][1] - np.clip(np.rint(mixed), 0, 255)).max() <= 1


def test_image_sequences_in_and_out(clip, tmp_path):
    frames = tmp_path / "in"
    frames.mkdir()
    depths = media.decoded(clip / "depth.mkv", "gray16le")
    for i, (_, color) in enumerate(media.decoded(clip / "rgb.mkv", "rgb24")[:5]):
        for name, array, fmt in ((f"c{i + 7:03d}.png", color, "rgb24"), (f"d{i + 7:03d}.png", depths[i][1], "gray16le")):
            av.VideoFrame.from_ndarray(array, format=fmt).to_image().save(frames / name) if fmt == "rgb24" else \
                _write_png16(frames / name, array)
    outputs = convert(frames / "c%03d.png", frames / "d%03d.png", tmp_path / "out" / "f%04d.png", layout="left",
                      direction="right-to-left", **CAMERA)
    assert outputs == [str(tmp_path / "out" / "f%04d.png")]
    assert sorted(os.listdir(tmp_path / "out")) == [f"f{i:04d}.png" for i in range(7, 12)]
    # right-to-left keeps the right eye (the source) and synthesises the left.
    color = media.decoded(clip / "rgb.mkv", "rgb24")[2][1]
    decoder = reproject.Decoder()
    model = reproject.StereoCamera(0.03, 4.0).parallax(W, "right-to-left")
    rgba = np.dstack([color, np.full((H, W), 255, np.uint8)])
    expected = reproject.warp(rgba, depths[2][1].astype(np.float32) * np.float32(0.001), decoder=decoder, model=model)
    written = media.decoded(tmp_path / "out" / "f0009.png", "rgb24")[0][1]
    assert np.array_equal(written, expected.color[..., :3])


def _write_png16(path, array):
    context = av.CodecContext.create("png", "w")
    frame = av.VideoFrame.from_ndarray(array, format="gray16le").reformat(format="gray16be")
    context.width, context.height, context.pix_fmt = frame.width, frame.height, "gray16be"
    path.write_bytes(b"".join(bytes(p) for p in list(context.encode(frame)) + list(context.encode(None))))


def test_exr_reader_reads_what_the_cli_writes(cli, tmp_path):
    completed = subprocess.run([cli, "scene", "--scene", "spheres", "--width", "64", "--height", "40", "--out-dir",
                                str(tmp_path), "--color-format", "exr", "--depth-format", "exr"], capture_output=True)
    assert completed.returncode == 0, completed.stderr
    subprocess.run([cli, "scene", "--scene", "spheres", "--width", "64", "--height", "40", "--out-dir",
                    str(tmp_path / "pfm"), "--color-format", "pfm"], check=True, capture_output=True)
    from reproject import _exr
    depth = _exr.read(str(tmp_path / "centre_depth.exr"), "depth")
    color = _exr.read(str(tmp_path / "centre.exr"), "color")
    pfm_depth = pfm.read(tmp_path / "pfm" / "centre_depth.pfm")
    assert depth.shape == (40, 64) and color.shape == (3, 40, 64)
    assert np.array_equal(depth, pfm_depth.reshape(40, 64))
    assert 0.0 < color.min() and color.max() <= 1.0


# ---- Streams and timing ---------------------------------------------------------------------------

def test_audio_copied_packet_for_packet_and_timing_kept(clip, tmp_path):
    out = convert(clip / "colour.mkv", clip / "depth.mkv", tmp_path / "o.mkv", segment_frames=7, **CAMERA)[0]

    def audio(path):
        with av.open(str(path)) as container:
            return [(p.pts, bytes(p)) for p in container.demux(audio=0) if p.size]
    assert len(audio(clip / "colour.mkv")) > 5 and audio(out) == audio(clip / "colour.mkv")
    assert media.frame_times(out) == media.frame_times(clip / "colour.mkv")


def test_variable_frame_rate_and_subtitles_kept(clip, tmp_path):
    gaps = [1, 1, 3, 1, 2, 5, 1, 1, 1, 2, 1, 4]  # ticks of 1/48 s: 48, 24, 16, 9.6 fps...
    pts = list(np.cumsum([0] + gaps))
    colors = [media.texture(W, H, k) for k in range(len(pts))]
    media.write_video(tmp_path / "vfr.mp4", colors, "yuv420p", codec="libx264", pts=pts,
                      time_base=fractions.Fraction(1, 48))
    media.write_video(tmp_path / "vfr_depth.mkv", [media.depth_codes(W, H, k) for k in range(len(pts))], "gray16le",
                      source_format="gray16le", pts=pts, time_base=fractions.Fraction(1, 48))
    out = convert(tmp_path / "vfr.mp4", tmp_path / "vfr_depth.mkv", tmp_path / "vfr_out.mp4", segment_frames=4,
                  **CAMERA)[0]
    assert media.frame_times(out) == media.frame_times(tmp_path / "vfr.mp4") == [p / 48 for p in pts]
    # Depth at other timestamps (another rate) is refused, naming the frame.
    media.write_video(tmp_path / "cfr_depth.mkv", [np.zeros((H, W), np.uint16)] * len(pts), "gray16le",
                      source_format="gray16le")
    with pytest.raises(ConvertError, match=r"depth '.*cfr_depth.mkv' frame 1 is at 0.0420 s but colour .* frame 1 at "
                                           r"0.0208 s"):
        convert(tmp_path / "vfr.mp4", tmp_path / "cfr_depth.mkv", tmp_path / "x.mp4", **CAMERA)
    # Subtitles (SubRip in Matroska) are copied packet for packet too.
    cues = tmp_path / "cues.mkv"
    _with_subtitles(tmp_path / "vfr.mp4", cues)
    out = convert(cues, tmp_path / "vfr_depth.mkv", tmp_path / "cues_out.mkv", **CAMERA)[0]

    def subtitles(path):
        with av.open(str(path)) as container:
            return [(p.pts, bytes(p)) for p in container.demux(subtitles=0) if p.size]
    assert len(subtitles(cues)) == 2 and subtitles(out) == subtitles(cues)


def _with_subtitles(video, out):
    """`video` remuxed into Matroska with two SubRip cues (read from an .srt file)."""
    srt = out.with_suffix(".srt")
    srt.write_text("1\n00:00:00,000 --> 00:00:00,150\none\n\n2\n00:00:00,200 --> 00:00:00,350\ntwo\n")
    with av.open(str(video)) as source, av.open(str(srt)) as cues, av.open(str(out), "w") as target:
        streams = {id(source.streams.video[0]): target.add_stream(template=source.streams.video[0]),
                   id(cues.streams.subtitles[0]): target.add_stream(template=cues.streams.subtitles[0])}
        packets = [p for p in source.demux(source.streams.video[0]) if p.size]
        packets += [p for p in cues.demux(cues.streams.subtitles[0]) if p.size]
        packets.sort(key=lambda p: float(p.dts * p.time_base))
        for packet in packets:
            packet.stream = streams[id(packet.stream)]
            target.mux(packet)


def test_hdr_color_metadata_and_ten_bit_samples_kept(tmp_path):
    tags = {"color_primaries": "bt2020", "color_trc": "smpte2084", "colorspace": "bt2020nc", "color_range": "tv"}
    frames = [media.texture(W, H, k, bits=16) for k in range(4)]
    media.write_video(tmp_path / "hdr.mkv", frames, "yuv444p10le", source_format="rgb48le", options=tags)
    media.write_video(tmp_path / "flat.mkv", [np.full((H, W), 3000, np.uint16)] * 4, "gray16le",
                      source_format="gray16le")
    # No parallax (separation 0): the eye is the source, sample for sample, in YUV 4:4:4 10-bit.
    out = convert(tmp_path / "hdr.mkv", tmp_path / "flat.mkv", tmp_path / "out.mkv", codec="ffv1", layout="left",
                  encoding="linear", separation=0.0, convergence=3.0)[0]
    with av.open(out) as container:
        assert reproject._media.color_tags(container, 0) == tags
    for (_, a), (_, b) in zip(media.decoded(tmp_path / "hdr.mkv"), media.decoded(out)):
        for plane in range(3):
            assert np.array_equal(reproject._media.plane(a, plane, "<u2"), reproject._media.plane(b, plane, "<u2"))
    # x265 10-bit carries the tags too, in its bitstream and in the container.
    out = convert(tmp_path / "hdr.mkv", tmp_path / "flat.mkv", tmp_path / "out265.mp4", codec="libx265",
                  pixel_format="yuv420p10le", **dict(CAMERA, depth_scale=0.001))[0]
    with av.open(out) as container:
        assert reproject._media.color_tags(container, 0) == tags
        assert container.streams.video[0].codec_context.pix_fmt == "yuv420p10le"


def test_relative_depth_moves_by_its_share_of_the_maximum(clip, tmp_path):
    media.write_video(tmp_path / "v.mkv", [np.full((H, W), 65535, np.uint16)] * 3, "gray16le",
                      source_format="gray16le")
    rgb = tmp_path / "c.mkv"
    media.write_video(rgb, [media.texture(W, H, k) for k in range(3)], "bgr0")
    out = convert(rgb, tmp_path / "v.mkv", tmp_path / "r.mkv", codec="ffv1", layout="right", relative_depth=True,
                  max_parallax=2 / W * 4, zero_plane=0.75, direction="left-to-right")[0]
    # v = 1 (65535), p = D W (0.75 - 1) = -2 px: the right eye's column x is the left's x + 2.
    source, shifted = media.decoded(rgb, "rgb24")[1][1], media.decoded(out, "rgb24")[1][1]
    assert np.array_equal(shifted[:, :W - 2], source[:, 2:])


# ---- Errors: the file and the frame named, nothing left behind --------------------------------------

def test_bad_input_is_named_and_leaves_nothing(clip, tmp_path):
    small = tmp_path / "small.mkv"
    media.write_video(small, [np.zeros((H // 2, W, 3), np.uint8)] * N, "bgr0")
    short = tmp_path / "short.mkv"
    media.write_video(short, [np.zeros((H, W), np.uint16)] * (N - 1), "gray16le", source_format="gray16le")
    broken = tmp_path / "broken.mkv"
    data = bytearray((clip / "rgb.mkv").read_bytes())
    data[len(data) // 2:len(data) // 2 + 3000] = bytes(3000)
    broken.write_bytes(data)
    before = listing(tmp_path)
    out = tmp_path / "o.mkv"
    cases = [
        ((clip / "rgb.mkv", small, out), r"colour '.*rgb.mkv' is 96x64 but depth '.*small.mkv' is 96x32", "input"),
        ((clip / "rgb.mkv", short, out), r"colour '.*rgb.mkv' has 20 frames but depth '.*short.mkv' has 19", "input"),
        ((clip / "rgb.mkv", clip / "rgb.mkv", out), r"depth '.*rgb.mkv' is bgr0, not grey", "input"),
        ((clip / "rgb.mkv", clip / "depth.mkv", clip / "rgb.mkv"), r"output '.*rgb.mkv' is the input", "settings"),
        ((broken, clip / "depth.mkv", out), r"colour '.*broken.mkv' (frame \d+|has \d+ frames|cannot)", "input"),
    ]
    for args, message, kind in cases:
        with pytest.raises(ConvertError, match=message) as raised:
            convert(*args, codec="ffv1", segment_frames=5, **CAMERA)
        assert raised.value.kind == kind, message
        assert listing(tmp_path) == before, message
    with pytest.raises(ConvertError, match=r"unknown layout 'side' \(sbsl, sbsr"):
        convert(clip / "rgb.mkv", clip / "depth.mkv", out, layout="side", **CAMERA)
    # A corrupt image in a sequence: its file and frame number.
    frames = tmp_path / "seq"
    frames.mkdir()
    for i, (_, color) in enumerate(media.decoded(clip / "rgb.mkv", "rgb24")[:4]):
        av.VideoFrame.from_ndarray(color, format="rgb24").to_image().save(frames / f"c{i}.png")
        _write_png16(frames / f"d{i}.png", media.decoded(clip / "depth.mkv", "gray16le")[i][1])
    (frames / "c2.png").write_bytes((frames / "c2.png").read_bytes()[:200])
    before = listing(tmp_path)
    with pytest.raises(ConvertError, match=r"colour '.*c2.png' \(frame 2\)"):
        convert(frames / "c%d.png", frames / "d%d.png", tmp_path / "seq_out.mkv", **CAMERA)
    assert listing(tmp_path) == before
    (frames / "c9.png").write_bytes(b"")
    with pytest.raises(ConvertError, match=r"has no frame 4 \('.*c4.png' is missing"):
        convert(frames / "c%d.png", frames / "d%d.png", tmp_path / "seq_out.mkv", **CAMERA)


def test_settings_errors(clip, tmp_path):
    args = (clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "o.mp4")
    for kwargs, message in [
            (dict(encoding="linear"), "convergence= .* is required"),
            (dict(relative_depth=True, convergence=3.0), "convergence cannot be used with relative_depth"),
            (dict(CAMERA, zero_plane=0.4), "zero_plane cannot be used with a depth that is not relative_depth"),
            (dict(CAMERA, codec="ffv1"), "ffv1 is not carried by .mp4"),
            (dict(CAMERA, pixel_format="rgb24"), "pixel format 'rgb24' is not one libx264 writes"),
            (dict(CAMERA, direction="centre-to-left"), "unknown direction 'centre-to-left'"),
            (dict(CAMERA, fov=60.0), "interaxial and fov go together"),
            (dict(CAMERA, method="fast"), "unknown method 'fast'")]:
        with pytest.raises(ConvertError, match=message):
            convert(*args, **kwargs)
    assert os.listdir(tmp_path) == []


# ---- The command line, and the package's face ------------------------------------------------------

def test_the_command_line(clip, tmp_path):
    run = [sys.executable, "-m", "reproject", "convert", "--color", str(clip / "rgb.mkv"), "--depth",
           str(clip / "depth.mkv"), "--encoding", "linear", "--depth-scale", "0.001"]
    done = subprocess.run(run + ["--convergence", "4", "--out", str(tmp_path / "o.mkv"), "--codec", "ffv1",
                                 "--layout", "abl"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"wrote {tmp_path / 'o.mkv'}\n" and done.stderr == ""
    assert media.decoded(tmp_path / "o.mkv", "rgb24")[0][1].shape == (2 * H, W, 3)
    usage = subprocess.run(run[:4], capture_output=True, text=True)
    assert usage.returncode == 2 and "required: --color" in usage.stderr
    # The C++ tool's exit codes for the same kinds of failure (docs/CLI.md "convert"), nothing left.
    small = tmp_path / "small.mkv"
    media.write_video(small, [np.zeros((H // 2, W), np.uint16)] * N, "gray16le", source_format="gray16le")
    (tmp_path / "folder.mkv").mkdir()
    before = listing(tmp_path)
    for flags, code, message in [
            (["--out", str(tmp_path / "x.mkv")], 2, r"convergence= \(--convergence\) is required"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--layout", "side"], 2, "unknown layout 'side'"),
            (["--convergence", "4", "--out", str(clip / "depth.mkv")], 2, "is the input"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--unknown-depth", "many"], 2,
             "unknown_depth 'many' is neither a number nor 'nan'"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--threads", "-3"], 2, "threads: -3 is negative"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--crf", "52"], 2,
             "crf 52 must be an integer in 0..51"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--retries", "-1"], 2,
             "retries -1 must be an integer >= 0"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--depth", str(tmp_path / "none.mkv")], 3,
             "depth '.*none.mkv' does not exist"),
            (["--convergence", "4", "--out", str(tmp_path / "x.mkv"), "--depth", str(small)], 3,
             "colour '.*rgb.mkv' is 96x64 but depth '.*small.mkv' is 96x32"),
            (["--convergence", "4", "--out", str(tmp_path / "missing" / "x.mkv")], 4,
             "cannot write '.*x.mkv': the folder '.*missing' does not exist"),
            (["--convergence", "4", "--out", str(tmp_path / "folder.mkv")], 4, "cannot write '.*folder.mkv': it is a "
                                                                             "directory")]:
        failed = subprocess.run(run + flags + ["--codec", "ffv1"], capture_output=True, text=True)
        assert failed.returncode == code and failed.stderr.startswith("reproject: error: "), (flags, failed.stderr)
        assert re.search(message, failed.stderr) and failed.stderr.count("\n") == 1, failed.stderr
        assert listing(tmp_path) == before, flags


def test_an_errors_kind_names_its_exit_code_and_survives_a_trip_through_pickle(clip, tmp_path):
    # Dask sends a worker's exception back pickled: its kind must come with it.
    for kind in ("settings", "input", "output", "failure"):
        error = pickle.loads(pickle.dumps(ConvertError("message", kind)))
        assert isinstance(error, ConvertError) and error.kind == kind and str(error) == "message"
    with pytest.raises(ConvertError) as raised:
        convert(clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "o.mkv", layout="side", **CAMERA)
    assert raised.value.kind == "settings"
    with pytest.raises(ConvertError) as raised:
        convert(clip / "rgb.mkv", tmp_path / "none.mkv", tmp_path / "o.mkv", **CAMERA)
    assert raised.value.kind == "input"
    with pytest.raises(ConvertError) as raised:
        convert(clip / "rgb.mkv", clip / "depth.mkv", tmp_path / "no" / "o.mkv", **CAMERA)
    assert raised.value.kind == "output"


def test_the_video_stub_names_every_public_name_with_its_parameters():
    import ast
    import typing
    from test_package import PACKAGE, runtime_parameters, stub_parameters
    stub = ast.parse((PACKAGE / "video.pyi").read_text())
    functions = {n.name: n for n in stub.body if isinstance(n, ast.FunctionDef)}
    public = set(reproject.video.__all__)
    assert public == {n for n in vars(reproject.video) if not n.startswith("_")} - {
        n for n, v in vars(reproject.video).items() if inspect.ismodule(v)}
    for name in public:
        value = getattr(reproject.video, name)
        if inspect.isfunction(value):
            assert runtime_parameters(value) == stub_parameters(functions[name]), name
            assert value.__doc__
        elif isinstance(value, type):
            assert any(isinstance(n, ast.ClassDef) and n.name == name for n in stub.body)
        else:
            assert any(isinstance(n, ast.AnnAssign) and n.target.id == name for n in stub.body), name
    layout = next(n for n in stub.body if isinstance(n, ast.Assign) and n.targets[0].id == "Layout")
    assert tuple(e.value for e in layout.value.slice.elts) == reproject.video.layouts
    assert "progress" in inspect.signature(reproject.video.convert).parameters and typing
