#!/usr/bin/env python3
"""compare-images.py A.exr B.exr [A.png B.png] — how far image A is from image B.

Prints one line: `rel_rmse=… rmse=… max_abs=… ldr_over_2=N of M`, where rel_rmse is the
root mean square difference of the linear RGB beauty (R, G, B of the EXRs) divided by B's
mean over all pixels and channels — envshadow's own definition (src/film.rs, image_error) —
and, with the PNGs, ldr_over_2 counts the pixels whose 8-bit value differs by more than 2 in
any channel. Needs the PyPI packages OpenEXR, numpy and Pillow.
"""
import sys

import numpy as np
import OpenEXR


def beauty(path):
    with OpenEXR.File(path) as f:
        ch = f.channels()
        # The OpenEXR bindings group R, G, B (and A) into one channel named after them.
        for name in ("RGB", "RGBA"):
            if name in ch:
                return np.asarray(ch[name].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)


def main():
    if len(sys.argv) not in (3, 5):
        sys.exit(__doc__.strip().splitlines()[0])
    a, b = beauty(sys.argv[1]), beauty(sys.argv[2])
    if a.shape != b.shape:
        sys.exit(f"compare-images.py: {sys.argv[1]} is {a.shape}, {sys.argv[2]} is {b.shape}")
    d = a - b
    rmse = float(np.sqrt(np.mean(d * d)))
    mean = float(np.mean(b))
    line = f"rel_rmse={rmse / mean if mean > 0 else 0.0:.6e} rmse={rmse:.6e} max_abs={float(np.max(np.abs(d))):.6e}"
    if len(sys.argv) == 5:
        from PIL import Image

        pa = np.asarray(Image.open(sys.argv[3]).convert("RGB"), dtype=np.int16)
        pb = np.asarray(Image.open(sys.argv[4]).convert("RGB"), dtype=np.int16)
        over = int(np.sum(np.max(np.abs(pa - pb), axis=-1) > 2))
        line += f" ldr_over_2={over} of {pa.shape[0] * pa.shape[1]}"
    print(line)


if __name__ == "__main__":
    main()
