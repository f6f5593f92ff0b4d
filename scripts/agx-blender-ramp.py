#!/usr/bin/env python3
"""Blender's AgX view on a grey ramp, for tests/data/views/agx-blender-grey-ramp.csv.

Evaluates the "AgX" view of the "sRGB" display of Blender's OpenColorIO config (the
config and LUTs Blender ships, as kept in github.com/EaryChow/AgX, commit 74852bd
"sync with Blender main": config.ocio plus luts/) with PyOpenColorIO, on linear Rec.709
greys from 2^-12 to 2^8 in quarter stops, and prints CSV: linear value, the sRGB-encoded
display value Blender shows.

    pip install 'opencolorio>=2.4'
    git clone https://github.com/EaryChow/AgX && git -C AgX checkout 74852bd
    python3 scripts/agx-blender-ramp.py AgX/config.ocio > tests/data/views/agx-blender-grey-ramp.csv

src/view.rs's test `agx_matches_blenders_grey_ramp` reads the file.
"""
import sys

import PyOpenColorIO as ocio


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: agx-blender-ramp.py CONFIG.ocio")
    config = ocio.Config.CreateFromFile(sys.argv[1])
    view = ocio.DisplayViewTransform(src="Linear Rec.709", display="sRGB", view="AgX")
    cpu = config.getProcessor(view).getDefaultCPUProcessor()
    print(f"# Blender's AgX (sRGB display) on linear greys; OpenColorIO {ocio.__version__},")
    print("# config github.com/EaryChow/AgX 74852bd; made by scripts/agx-blender-ramp.py")
    print("linear,display")
    for k in range(-48, 33):
        v = 2.0 ** (k / 4)
        rgb = cpu.applyRGB([v, v, v])
        print(f"{v:.9g},{rgb[1]:.7f}")


if __name__ == "__main__":
    main()
