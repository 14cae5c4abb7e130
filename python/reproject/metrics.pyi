# Types of reproject.metrics (documented at run time: help(reproject.metrics.ssim)).
from typing import Any

import numpy.typing as npt

def psnr(a: npt.NDArray[Any], b: npt.NDArray[Any], mask: npt.ArrayLike | None = None,
         data_range: float | None = None) -> float: ...
def ssim(a: npt.NDArray[Any], b: npt.NDArray[Any], mask: npt.ArrayLike | None = None,
         data_range: float | None = None) -> float: ...
