# Every method on the teddy pair scores what tests/test_teddy.cpp prints, to the digits it prints.
import numpy as np
import pytest

import reproject
import teddy

# As printed by Teddy.EveryMethodReachesItsFloor (PSNR dB, MAE, scored pixels, hit %, hole %).
CXX_PRINTS = {
    "scanline": ("29.163", "5.034", 149369, "99.10", "0.83"),
    "march16": ("27.785", "5.352", 149369, "99.38", "0.52"),
    "single": ("20.401", "11.191", 149369, "99.17", "0.49"),
    "secant": ("29.163", "5.034", 149369, "99.10", "0.83"),
    "exact": ("29.163", "5.034", 149369, "99.10", "0.83"),
}
CXX_UNWARPED = ("12.863", "39.057")


@pytest.fixture(scope="module")
def pair(data_dir):
    left, right, disp_left, disp_right = teddy.load(data_dir)
    return (left.astype(np.float32), right.astype(np.float32), teddy.fill_unknown(disp_left),
            teddy.visible_in_both(disp_left, disp_right))


def test_scored_pixels_and_unwarped(pair):
    left, right, _, mask = pair
    psnr, mae, scored = teddy.score(left, right, mask)
    print(f"[ teddy    ] {'(none)':<9} {psnr:8.3f} {mae:8.3f} {scored:8d}")
    assert scored == 149369
    assert (f"{psnr:.3f}", f"{mae:.3f}") == CXX_UNWARPED


@pytest.mark.parametrize("method", reproject.methods)
def test_method_scores_as_the_cxx_test(pair, method):
    left, right, disparity, mask = pair
    result = reproject.warp(left, disparity, encoding="disparity", direction="left-to-right", method=method)
    psnr, mae, scored = teddy.score(result.color, right, mask)
    hit = 100.0 * np.mean(result.status[mask] == 0)
    hole = 100.0 * np.mean(result.status[mask] == 1)
    print(f"[ teddy    ] {method:<9} {psnr:8.3f} {mae:8.3f} {scored:8d} {hit:7.2f} {hole:7.2f}")
    assert (f"{psnr:.3f}", f"{mae:.3f}", scored, f"{hit:.2f}", f"{hole:.2f}") == CXX_PRINTS[method]
