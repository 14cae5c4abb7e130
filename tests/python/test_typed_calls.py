# Typed calls across the package's API, run by pytest and checked by mypy --strict against the
# package's stubs (pyproject.toml's [tool.mypy]; tests/python/test_types.py runs it): every
# annotation below is what the stub promises, and the calls run, so the two cannot disagree.
import numpy as np
import numpy.typing as npt

import reproject
import reproject.metrics


def test_reprojection_calls_are_typed() -> None:
    s: reproject.SceneViews = reproject.scene("pole", 64, 32, fov=50.0, encoding="reversed", threads=1)
    width: int = s.width
    fov_radians: float = s.horizontal_fov
    method: reproject.Method = "secant"
    fill: reproject.HoleFill = "foreground"
    edge: reproject.EdgeMode = "mirror"
    right: reproject.Result = reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, method=method,
                                             hole_fill=fill, edge=edge, threads=1)
    status: npt.NDArray[np.uint8] = right.status
    source_x: npt.NDArray[np.float32] = right.source_x
    again: reproject.Result = reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, method=method,
                                             hole_fill=fill, edge=edge, threads=1, out=right)
    assert again.color is right.color and status.shape == source_x.shape == (32, width) and fov_radians > 0
    left, right_eye = reproject.warp_pair(s.color, s.depth, encoding="reversed", near=s.near, far=s.far,
                                          separation=s.camera.separation, convergence=s.camera.convergence)
    pair: reproject.PairResult = reproject.warp_pair(s.color, s.depth, decoder=s.decoder, convergence=3.5)
    assert left.color.shape == right_eye.color.shape == pair.left.color.shape
    arch: reproject.Arch = reproject.selected_arch()
    assert reproject.arch_supported(arch)
    name: reproject.SceneName = s.name
    assert name in reproject.scenes and method in reproject.methods


def test_models_are_typed() -> None:
    decoder = reproject.Decoder.from_near_far("standard", 1.0, 20.0)
    encoding: reproject.Encoding = decoder.encoding
    w: float = decoder.inverse_depth(0.5)
    ws: npt.NDArray[np.float32] = decoder.inverse_depth(np.zeros((2, 3), np.float32))
    z: float = decoder.linear_depth(decoder.encode(4.0))
    direction: reproject.Direction = "centre_to_right"
    model = reproject.ParallaxModel.from_stereo(0.03, 3.5, 1000, direction)
    p: float = model.parallax(w)
    camera = reproject.StereoCamera.from_physical(0.065, 1.3, 3.5)
    eye: reproject.Eye = "left"
    matrix: npt.NDArray[np.float32] = camera.projection_d3d(np.eye(4, dtype=np.float32), eye)
    assert encoding == "standard" and ws.shape == (2, 3) and abs(z - 4.0) < 1e-4 and matrix.shape == (4, 4)
    assert abs(p - (model.a + model.b * w)) < 1e-4 and camera.parallax(1000, "left-to-right").a > 0


def test_stereo_helpers_are_typed() -> None:
    s = reproject.scene("boxes", 64, 32)
    budget = reproject.parallax_budget(s.depth, s.decoder, s.camera, histogram_bins=8)
    histogram: npt.NDArray[np.int64] | None = budget.histogram
    percentiles: tuple[float, ...] = budget.percentile
    assert histogram is not None and int(histogram.sum()) == budget.pixels and len(percentiles) == 7
    mono = reproject.ViewFrustum.perspective(s.horizontal_fov, 64, 32, s.near, s.far)
    culling: reproject.CullingFrustum = reproject.stereo_culling_frustum(mono, s.camera)
    inside: bool = culling.contains(0.0, 0.0, 5.0)
    reconstruction = reproject.make_screen_to_view(mono, "standard", 64, 32)
    x, y, z = reproject.screen_to_view(reconstruction, s.depth)
    point: tuple[float, float, float] = reconstruction.at_pixel(10.0, 5.0, float(s.depth[5, 10]))
    model = s.camera.parallax(64, "left-to-right")
    picked: reproject.PickResult = reproject.pick(s.left_depth, s.right_depth, s.decoder, model, 32.0, 16)
    source: reproject.PickSource = picked.source
    left, right = reproject.place_at_depth(0.0, 0.0, 5.0, s.camera, s.decoder)
    dilated: npt.NDArray[np.float32] = reproject.dilate_nearer_depth(s.depth, s.decoder, 2)
    assert inside and x.shape == y.shape == z.shape == dilated.shape == (32, 64) and len(point) == 3
    assert source in ("both", "left", "right", "none") and len(left) == len(right) == 4


def test_metrics_are_typed() -> None:
    s = reproject.scene("spheres", 64, 32)
    psnr: float = reproject.metrics.psnr(s.color, s.right, mask=s.right_visible)
    ssim: float = reproject.metrics.ssim(s.color, s.right, data_range=1.0)
    version: str = reproject.__version__
    assert 0.0 < ssim < 1.0 and psnr > 0.0 and version.count(".") == 2
