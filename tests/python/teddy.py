# The Middlebury teddy pair as tests/test_teddy.cpp uses it: the left view (im2) with its
# ground-truth disparity (disp2, value / 4, unknowns filled with the farther known row neighbour),
# the right view (im6) to compare with, and the pixels visible in both views.
import numpy as np
from PIL import Image

DISPARITY_SCALE = 0.25


def load(data_dir):
    def read(name):
        return np.asarray(Image.open(data_dir / "teddy" / name))

    return read("im2.png"), read("im6.png"), read("disp2.png"), read("disp6.png")


def fill_unknown(stored):
    """Disparity in pixels; each unknown (0) takes the smaller of its nearest known row neighbours
    (the one that exists if only one does; 0 if the row has none), as test_teddy.cpp's rule."""
    disparity = stored.astype(np.float32) * np.float32(DISPARITY_SCALE)
    known = stored != 0
    width = stored.shape[1]
    columns = np.arange(width)
    # Index of the nearest known pixel at or before / at or after each column (-1 / width: none).
    before = np.maximum.accumulate(np.where(known, columns, -1), axis=1)
    after = np.minimum.accumulate(np.where(known, columns, width)[:, ::-1], axis=1)[:, ::-1]
    rows = np.arange(stored.shape[0])[:, None]
    left = np.where(before >= 0, disparity[rows, np.clip(before, 0, width - 1)], np.inf)
    right = np.where(after < width, disparity[rows, np.clip(after, 0, width - 1)], np.inf)
    filled = np.minimum(left, right)
    filled[np.isinf(filled)] = 0.0
    return np.where(known, disparity, filled).astype(np.float32)


def visible_in_both(disp_left, disp_right):
    """Right-view pixels with a known disparity whose left partner (nearest pixel to x + d) is
    inside, known and agrees to 1 px."""
    height, width = disp_right.shape
    d_right = disp_right.astype(np.float32) * np.float32(DISPARITY_SCALE)
    x = np.arange(width, dtype=np.float32)[None, :]
    partner = np.floor(x + d_right + np.float32(0.5)).astype(np.int64)
    inside = (disp_right != 0) & (partner >= 0) & (partner < width)
    rows = np.broadcast_to(np.arange(height)[:, None], (height, width))
    stored_left = disp_left[rows, np.clip(partner, 0, width - 1)]
    d_left = stored_left.astype(np.float32) * np.float32(DISPARITY_SCALE)
    return inside & (stored_left != 0) & (np.abs(d_left - d_right) <= 1.0)


def score(view, truth, mask):
    """PSNR (peak 255) and mean absolute error over the 3 channels of the masked pixels."""
    difference = view[mask][:, :3].astype(np.float64) - truth[mask][:, :3].astype(np.float64)
    mse = np.mean(difference * difference)
    return 10.0 * np.log10(255.0 * 255.0 / mse), np.mean(np.abs(difference)), int(mask.sum())
