"""reproject: synthesise the other eye of a stereo pair from one view (colour + depth) by moving
every pixel horizontally by its parallax, over NumPy arrays.

    import reproject
    s = reproject.scene("room", 960, 540)
    right = reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, method="secant")

warp and warp_pair reproject; Decoder, ParallaxModel and StereoCamera describe the depth and the
stereo camera; the stereo helpers (parallax_budget, stereo_culling_frustum, pick,
make_screen_to_view, screen_to_view, place_at_depth, dilate_nearer_depth) work around it; scene
ray-casts the built-in scenes; reproject.metrics scores images (PSNR, SSIM). The kernels are the
C++ library's (the compiled module reproject._reproject); the GIL is released while they run.

Units: pixels for parallax and columns; view-space units (the renderer's, the same as near, far
and the depth itself) for depths and distances; radians for angles unless a name says degrees.
Names of options are strings, typed below as Literal aliases (Method, HoleFill, ...).
"""
from typing import Literal

from . import _reproject
from ._reproject import (
    CullingFrustum,
    Decoder,
    PairResult,
    ParallaxBudget,
    ParallaxModel,
    PickResult,
    Result,
    SceneViews,
    ScreenToView,
    StereoCamera,
    ViewFrustum,
    __version__,
    _debug_max_concurrent_calls,
    _debug_reset_counters,
    budget_percentiles,
    arches,
    methods,
    scenes,
)
from ._signatures import forwards_to as _forwards_to

# The names each option takes (the library's name tables: tests/python/test_package.py checks
# that these lists hold exactly the names the library accepts).
Method = Literal["scanline", "march16", "single", "secant", "exact"]
Arch = Literal["scalar", "sse", "avx2", "avx512", "neon"]
HoleFill = Literal["background", "foreground", "none"]
EdgeMode = Literal["clamp", "none", "black", "mirror"]
Encoding = Literal["linear", "standard", "gl_ndc", "reversed", "reversed_infinite", "infinite", "disparity"]
Direction = Literal["left-to-right", "right-to-left", "centre-to-left", "centre-to-right",
                    "left_to_right", "right_to_left", "centre_to_left", "centre_to_right"]
DepthFormat = Literal["float32", "unorm16", "unorm24_s8", "s8_unorm24", "rgba8_packed_linear"]
ColorSpace = Literal["linear", "srgb"]
Eye = Literal["left", "right"]
SceneName = Literal["room", "boxes", "pole", "spheres", "near", "edge"]
PickSource = Literal["both", "left", "right", "none"]
del Literal

__all__ = [
    "metrics", "video",
    # options' names
    "Method", "Arch", "HoleFill", "EdgeMode", "Encoding", "Direction", "DepthFormat", "ColorSpace", "Eye", "SceneName",
    "PickSource", "methods", "arches", "scenes",
    # reprojection
    "Decoder", "ParallaxModel", "StereoCamera", "Result", "PairResult", "warp", "warp_pair", "arch_supported",
    "selected_arch",
    # the stereo helpers (stereo.hpp)
    "ParallaxBudget", "budget_percentiles", "parallax_budget", "ViewFrustum", "CullingFrustum",
    "stereo_culling_frustum", "PickResult", "pick", "ScreenToView", "make_screen_to_view", "screen_to_view",
    "place_at_depth", "dilate_nearer_depth",
    # the built-in scenes
    "SceneViews", "scene",
]


@_forwards_to(_reproject.warp)
def warp(color, depth, *, color_space="linear", depth_format=None, linear_range=None, encoding=None, near=None,
         far=None, decoder=None, separation=None, convergence=None, direction=None, model=None, method="exact",
         max_negative_parallax=None, hole_threshold=1.0, hole_fill="background", edge="clamp", guard=0,
         probe_parallax=None, march_steps=16, secant_max_steps=256, arch=None, threads=0, out=None):
    """Synthesises another eye from one view (colour + depth): reproject() of reproject.hpp.

    color: float32 (H, W), (H, W, C) or (C, H, W) with C = 1..4. Planes and (H, W, 4) arrays
      whose columns are consecutive are read in place (any row stride, crops included); packed
      (H, W, 2|3) colour (Pillow's layout) is copied once into planes, since the library has no
      such layout. Anything else (e.g. a[:, ::2]) raises ValueError.
      Engine colour, (H, W, 4) RGBA read in place (each pixel's 4 channels consecutive): uint8 is
      rgba8, blended as the byte values (color_space='linear', the default), or rgba8_srgb with
      color_space='srgb' (R, G, B decoded from sRGB, blended in linear light, encoded back, within one code);
      float16 is rgba16f.
    depth: float32 (H, W), the stored depth value, read in place under the same rule. Engine
      depth buffers, read in place with any row stride: uint16 (H, W) is D16 (unorm16); uint32
      (H, W) is D24S8 and needs depth_format='unorm24_s8' (depth in bits 0-23: D3D, Vulkan) or
      's8_unorm24' (depth in bits 8-31: OpenGL); uint8 (H, W, 4) needs
      depth_format='rgba8_packed_linear' and linear_range=(near, far), the view-space depths its
      packed values 0 and 1 stand for (use it with the linear encoding, the default).
      depth_format=None: decided by the dtype; a name must fit the dtype.

    The depth decoder: encoding= (Encoding: 'linear', the default, 'standard', 'gl_ndc',
      'reversed', 'reversed_infinite', 'infinite', 'disparity'), near= and far= (view-space
      units; not with linear or disparity); or decoder=Decoder instead. It decodes the value each
      format stores (u / 65535, u / 16777215, or the packed linear depth).
    The parallax: separation= (interaxial / virtual screen width, default 0.03), convergence=
      (view-space distance of the zero-parallax plane: required for depth), direction=
      (Direction, default 'centre-to-right'; for a disparity map, p = -d with the default
      'left-to-right', p = +d with 'right-to-left'); or model=ParallaxModel instead.
    Options, with the C++ names and defaults (reproject.hpp's Options):
      method='exact' (Method: 'scanline', 'march16', 'single', 'secant', 'exact');
      max_negative_parallax=None: the largest crossed parallax searched, pixels >= 0 (None: the
        frame's most negative parallax, so nothing is clipped);
      hole_threshold=1.0: pixels of parallax between neighbours above which they are a wall;
      hole_fill='background' (HoleFill: 'background', 'foreground', 'none');
      edge='clamp' (EdgeMode: 'clamp', 'none', 'black', 'mirror'): pixels outside the source;
      guard=0: columns of guard band on each side (target width = source width - 2 guard);
      probe_parallax=None: the parallax of the one sample of method 'single', pixels (None: the
        parallax at infinity);
      march_steps=16: the steps of 'march16', 1..1024;
      secant_max_steps=256: the most steps of 'secant' per 16-pixel tile, 1..4096;
      arch=None (Arch: 'scalar', 'sse', 'avx2', 'avx512', 'neon'; None: selected_arch());
      threads=0: threads of the library's pool (0: one per hardware thread, 1: this one only).
    out: None (new arrays), a Result of an earlier call (written in place: no allocation), or a
      colour array (then only colour is written). Its arrays must have the source's dtypes and
      shapes.

    Returns a Result: color (the source's form and dtype), depth (the source depth's dtype and
    format: stencil bits and the packed format's alpha come from the source pixel the output
    interpolates from), status (uint8: 0 hit, 1 hole, 2 outside, 3 clipped), source_x (float32,
    the source column). The GIL is released while the kernels run. Ctrl-C (KeyboardInterrupt, or
    any signal handler that raises) stops a call made from the main thread within about 10 ms plus
    a block of rows; the outputs it was writing are then unspecified.
    Errors: TypeError for an argument of the wrong type or dtype (naming it and what it takes);
    ValueError with the library's message for everything else.
    """


@_forwards_to(_reproject.warp_pair)
def warp_pair(color, depth, *, color_space="linear", depth_format=None, linear_range=None, encoding=None, near=None,
              far=None, decoder=None, separation=None, convergence=None, direction=None, model=None, method="exact",
              max_negative_parallax=None, hole_threshold=1.0, hole_fill="background", edge="clamp", guard=0,
              probe_parallax=None, march_steps=16, secant_max_steps=256, arch=None, threads=0, out_left=None,
              out_right=None):
    """The centre view to both eyes in one call (reproject_pair of reproject.hpp): a PairResult.

    The right eye is made with the stereo camera's sigma = +1/2 (or model=, the centre-to-right
    model), the left with its mirror. The arguments are warp()'s, with the same defaults; direction=
    is refused (ValueError), since the eyes are always the left and the right one of the centre
    view, and so is a disparity map (it belongs to one eye). out_left= and out_right= are as warp's
    out=. The result unpacks as (left, right). Ctrl-C stops the call as it stops warp().
    """


@_forwards_to(_reproject.arch_supported)
def arch_supported(arch):
    """Whether the kernels for `arch` (Arch: 'scalar', 'sse', 'avx2', 'avx512', 'neon') are compiled
    in and this CPU runs them. An unknown name is a ValueError."""


@_forwards_to(_reproject.selected_arch)
def selected_arch():
    """The instruction set (Arch) calls use when arch= is unset: the best one supported, or the one
    named by the environment variable REPROJECT_FORCE_ARCH when it is supported."""


@_forwards_to(_reproject.parallax_budget)
def parallax_budget(depth, decoder, camera, *, eye_separation=None, display_width=0, parallax_limit=None,
                    histogram_bins=0, histogram_min=None, histogram_max=None):
    """The parallax budget of a depth buffer under a stereo camera (stereo.hpp): a ParallaxBudget.

    depth: float32 (H, W), the stored values, decoded by `decoder` (Decoder); camera: StereoCamera.
    The parallax is left eye -> right eye, in pixels of the display width W:
    p = S W (1 - c / z). Keywords (BudgetOptions):
      eye_separation=None: E = interocular / physical screen width (None: the camera's separation);
      display_width=0: W, pixels the image spans on that screen (0: the depth's width);
      parallax_limit=None: |p| above this many pixels is uncomfortable (None: E W);
      histogram_bins=0: bins of the parallax histogram (0: none), over histogram_min ..
        histogram_max pixels (both or neither; neither: the finite parallax present).
    The result holds min, max and the percentiles (budget_percentiles) of p in pixels and in units
    of E W (`_of_eyes`), the shares (0..1) of pixels beyond the limit, nearer than c / 2, farther
    than 100 c and any of them, and `histogram` (int64 counts, or None). GIL released.
    """


@_forwards_to(_reproject.stereo_culling_frustum)
def stereo_culling_frustum(mono, camera):
    """One frustum that holds both eyes' frusta (stereo.hpp): cull once for two eyes.

    mono: the perspective ViewFrustum of the centre camera (view-space units); camera: the
    StereoCamera. Returns a CullingFrustum: the mono frustum pulled back by `pull_back` view-space
    units and widened by S times its half-width on each side, also as six planes (6, 4).
    """


@_forwards_to(_reproject.pick)
def pick(left_depth, right_depth, decoder, left_to_right, cursor_x, cursor_y, *, max_negative_parallax=None,
         hole_threshold=1.0, agreement=0.25):
    """What is under a cursor, from both eyes' depth buffers (stereo.hpp): a PickResult.

    left_depth, right_depth: float32 (H, W) of one size and encoding, decoded by `decoder`;
    left_to_right: the left -> right ParallaxModel; cursor_x: the mono (centre-eye) column, pixels
    (fractional allowed); cursor_y: the row. Keywords (PickOptions, pixels of parallax):
      max_negative_parallax=None: the largest crossed parallax searched (None: the nearest in
        either eye's row);
      hole_threshold=1.0: an eye's answer is on a wall (hidden from it) when its segment changes
        the eye -> mono parallax by more than this;
      agreement=0.25: within this, two readings agree.
    The result: source (PickSource: 'both', 'left', 'right', 'none'), parallax (pixels),
    inverse_depth, depth (view-space units), left_x and right_x (columns in each eye).
    """


@_forwards_to(_reproject.make_screen_to_view)
def make_screen_to_view(frustum, encoding, width, height):
    """Screen -> view-space reconstruction constants (stereo.hpp): a ScreenToView.

    frustum: the ViewFrustum the depth was rendered with; encoding: how the depth is stored
    (Encoding; perspective takes all but 'disparity', orthographic 'linear', 'standard',
    'reversed' and 'gl_ndc'); width, height: the viewport in pixels. The constants are computed from
    the frustum's edges in double, each rounded to float once, so far and off-centre points keep
    their precision.
    """


@_forwards_to(_reproject.screen_to_view)
def screen_to_view(reconstruction, depth, *, out_x=None, out_y=None, out_z=None):
    """View-space x, y, z at every pixel centre of `depth` (stereo.hpp): a tuple of three arrays.

    reconstruction: a ScreenToView (make_screen_to_view) of depth's width and height; depth: float32
    (H, W), the stored values. out_x, out_y, out_z: None (new arrays) or writable float32 (H, W)
    arrays, written in place. View-space units, z the positive distance. GIL released.
    """


@_forwards_to(_reproject.place_at_depth)
def place_at_depth(ndc_x, ndc_y, z, camera, decoder):
    """Both eyes' clip positions of a 2D element (cursor, label, HUD) seen at a depth (stereo.hpp).

    ndc_x, ndc_y: the element's mono position in NDC (-1..1); z: the view depth it is seen at
    (view-space units, > 0, inf allowed); camera: StereoCamera; decoder: the Decoder of the depth
    buffer it is tested against (not disparity). Returns (left, right), each (x, y, z, w) with
    z the stored depth and w = 1: the eyes' images are S W (1 - c / z) pixels apart.
    """


@_forwards_to(_reproject.dilate_nearer_depth)
def dilate_nearer_depth(depth, decoder, radius, *, out=None):
    """The halo pre-filter (stereo.hpp): each depth becomes the nearest (largest decoded 1/z) within
    `radius` columns of its row, so that silhouettes' anti-aliased edge pixels move with the
    foreground instead of leaving a halo on the background.

    depth: float32 (H, W), decoded by `decoder`; radius: columns, >= 0 (0 copies); out: None (a new
    array) or a writable float32 (H, W) array that does not overlap depth. Returns the output.
    GIL released.
    """


@_forwards_to(_reproject.scene)
def scene(name="room", width=960, height=540, *, fov=60.0, encoding="standard", separation=None, convergence=None,
          offset=0.0, threads=0):
    """Ray-casts a built-in scene for the centre, left and right eyes: a SceneViews.

    name: SceneName ('room', the default: all of the below in one room; 'boxes', 'pole',
    'spheres', 'near', 'edge'); width, height: pixels, 1..16384; fov: the horizontal field of view
    in degrees; encoding: how the depth is stored (Encoding, not 'disparity'); separation,
    convergence: the stereo camera (None: the scene's own: 0.03 and 3.5); offset: the whole rig moved
    sideways by this many interaxials (each eye's sigma shifted, the convergence plane kept: a camera
    path, as reproject.video.scene_video renders it); threads: as warp's.
    Warp s.color, s.depth with decoder=s.decoder and separation=s.camera.separation,
    convergence=s.camera.convergence to compare with s.left / s.right on s.left_visible /
    s.right_visible. GIL released while it renders.
    """


from . import metrics  # noqa: E402  (after the names it documents; it imports nothing from here)
from . import video  # noqa: E402  (PyAV, Dask and tqdm are imported when it runs, not here)
