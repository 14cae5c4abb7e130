# The decoder, the parallax model, the options as keyword arguments, warp_pair and the arch
# queries: the same numbers and names as the C++ API.
import inspect
import os
import platform
import subprocess
import sys

import numpy as np
import pytest

import reproject


def test_decoder_factories():
    d = reproject.Decoder.from_near_far("standard", 1.0, 20.0)
    assert (d.encoding, d.near, d.far) == ("standard", 1.0, 20.0)
    # w = 1/n + d (n - f)/(n f)
    assert d.A == np.float32((1.0 - 20.0) / 20.0) and d.B == np.float32(1.0)
    assert abs(d.linear_depth(d.encode(4.0)) - 4.0) < 1e-5
    assert d.inverse_depth(np.zeros((2, 3), np.float32)).shape == (2, 3)
    assert reproject.Decoder("reversed", near=0.5, far=100).encoding == "reversed"
    assert reproject.Decoder.linear().encoding == "linear" and reproject.Decoder.disparity().encoding == "disparity"
    n, f = 0.5, 100.0
    d3d = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, f / (f - n), 1], [0, 0, -n * f / (f - n), 0]], np.float32)
    m = reproject.Decoder.from_d3d_projection(d3d, "standard")
    assert abs(m.near - n) < 1e-5 and abs(m.far - f) < 1e-2
    gl = np.zeros(16, np.float32)  # column-major: M[r][c] = m[4c + r]
    gl[0], gl[5], gl[10], gl[11], gl[14] = 1, 1, -(f + n) / (f - n), -1, -2 * f * n / (f - n)
    g = reproject.Decoder.from_gl_projection(gl, "gl_ndc")
    assert abs(g.near - n) < 1e-4 and abs(g.far - f) < 0.1
    with pytest.raises(ValueError, match="near plane -1"):
        reproject.Decoder.from_near_far("standard", -1, 20)
    with pytest.raises(ValueError, match="unknown encoding 'log'"):
        reproject.Decoder("log")
    with pytest.raises(ValueError, match="16"):
        reproject.Decoder.from_d3d_projection(np.eye(3), "standard")


def test_parallax_factories():
    m = reproject.ParallaxModel.from_stereo(0.03, 3.5, 1000, "left-to-right")
    assert (m.a, m.b) == (np.float32(30.0), np.float32(-105.0))
    c = reproject.ParallaxModel.from_stereo(0.03, 3.5, 1000, "centre_to_left")
    assert (c.a, c.b) == (np.float32(-15.0), np.float32(52.5))
    p = reproject.ParallaxModel.from_physical(0.065, 1.3, 3.5, 1000, "left-to-right")
    assert abs(p.a - 50.0) < 1e-4
    d = reproject.ParallaxModel.from_disparity()
    assert (d.a, d.b) == (0.0, -1.0) and reproject.ParallaxModel.from_disparity("right-to-left").b == 1.0
    assert float(m.parallax(1 / 3.5)) == pytest.approx(0.0, abs=1e-5)
    camera = reproject.StereoCamera(0.03, 3.5)
    same = camera.parallax(1000, "left-to-right")
    assert (same.a, same.b) == (m.a, m.b)
    # A D3D perspective (clip w = z): the right eye's P[2][0] += S, P[3][0] -= S c.
    mono = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1.01, 1], [0, 0, -0.5, 0]], np.float32)
    right = camera.projection_d3d(mono, "right")
    assert right[2, 0] == np.float32(0.03) and right[3, 0] == np.float32(-0.03 * 3.5)
    assert camera.projection_gl(mono.T, "left").shape == (4, 4)
    with pytest.raises(ValueError, match="convergence"):
        reproject.ParallaxModel.from_stereo(0.03, 0.0, 1000, "left-to-right")
    with pytest.raises(ValueError, match="not finite|finite"):
        reproject.ParallaxModel(float("nan"), 1.0)
    with pytest.raises(ValueError, match="unknown direction 'up'"):
        reproject.ParallaxModel.from_stereo(0.03, 3.5, 1000, "up")


def test_options_are_keywords_with_the_cxx_names_and_defaults():
    # reproject.hpp's Options, field by field, with its defaults (unset optionals: None).
    cxx = {"method": "exact", "max_negative_parallax": None, "hole_threshold": 1.0, "hole_fill": "background",
           "edge": "clamp", "guard": 0, "probe_parallax": None, "march_steps": 16, "secant_max_steps": 256,
           "arch": None, "threads": 0}
    for function in (reproject.warp, reproject.warp_pair):
        parameters = inspect.signature(function).parameters
        for name, default in cxx.items():
            assert parameters[name].kind is inspect.Parameter.KEYWORD_ONLY, (function, name)
            assert parameters[name].default == default and type(parameters[name].default) is type(default), \
                (function, name, parameters[name].default)


def test_keyword_forms_agree():
    s = reproject.scene("boxes", 200, 100)
    by_names = reproject.warp(s.color, s.depth, encoding="standard", near=1, far=20, separation=0.03,
                              convergence=3.5, direction="centre-to-right")
    by_objects = reproject.warp(s.color, s.depth, decoder=s.decoder,
                                model=reproject.StereoCamera(0.03, 3.5).parallax(200, "centre-to-right"))
    assert np.array_equal(by_names.color, by_objects.color)
    left, right = reproject.warp_pair(s.color, s.depth, decoder=s.decoder, separation=0.03, convergence=3.5)
    to_left = reproject.warp(s.color, s.depth, decoder=s.decoder, separation=0.03, convergence=3.5,
                             direction="centre-to-left")
    assert np.array_equal(right.color, by_names.color) and np.array_equal(left.color, to_left.color)
    for method in reproject.methods:
        r = reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, method=method, hole_fill="none",
                           edge="black", march_steps=8, secant_max_steps=64, probe_parallax=0.0,
                           max_negative_parallax=20.0, hole_threshold=0.5, threads=1)
        assert r.status.max() <= 3
    with pytest.raises(ValueError, match="decoder= cannot be used with encoding="):
        reproject.warp(s.color, s.depth, decoder=s.decoder, encoding="standard", convergence=3.5)
    with pytest.raises(ValueError, match="convergence= is required"):
        reproject.warp(s.color, s.depth, decoder=s.decoder)
    with pytest.raises(ValueError, match="unknown hole_fill 'grey'"):
        reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, hole_fill="grey")
    with pytest.raises(ValueError, match="disparity"):
        reproject.warp_pair(s.color, s.depth, encoding="disparity")


def test_arch_queries():
    assert reproject.arch_supported("scalar")
    assert reproject.arch_supported(reproject.selected_arch())
    assert reproject.arches[0] == "scalar" and len(set(reproject.arches)) == len(reproject.arches)
    assert reproject.selected_arch() in reproject.arches
    with pytest.raises(ValueError, match="unknown arch 'avx1024'"):
        reproject.arch_supported("avx1024")
    # One processor family's sets at a time: the x86 sets on x86-64, neon on AArch64.
    machine = platform.machine().lower()
    if machine in ("x86_64", "amd64"):
        assert not reproject.arch_supported("neon")
    elif machine in ("aarch64", "arm64"):
        assert reproject.arch_supported("neon")
        assert not any(reproject.arch_supported(a) for a in ("sse", "avx2", "avx512"))
    code = "import reproject; print(reproject.selected_arch())"
    env = dict(os.environ, REPROJECT_FORCE_ARCH="scalar")
    assert subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True).stdout.strip() == "scalar"
    s = reproject.scene("pole", 64, 32)
    unsupported = [a for a in reproject.arches if not reproject.arch_supported(a)]
    for arch in unsupported:
        with pytest.raises(ValueError, match=arch):
            reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, arch=arch)
