# PFM files for the CLI comparisons: "PF" (RGB) or "Pf" (grey), little-endian (negative scale),
# rows stored bottom to top.
import numpy as np


def write(path, image):
    image = np.asarray(image, dtype="<f4")
    kind = "PF" if image.ndim == 3 else "Pf"
    with open(path, "wb") as f:
        f.write(f"{kind}\n{image.shape[1]} {image.shape[0]}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(image[::-1]).tobytes())


def read(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    shape = (height, width, 3) if kind == b"PF" else (height, width)
    return data.reshape(shape)[::-1].astype(np.float32)
