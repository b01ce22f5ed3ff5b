#!/usr/bin/python3
"""A picture of where a render differs from the true surface.

  error_map.py REF_PREFIX CANDIDATE.exr OUT.png [MAX_DEG]

Per pixel: where both are covered, the angle between our normal and refsurf's,
black (0 deg) through red and yellow to white (MAX_DEG, default 45, and above);
covered by the true surface only (a hole or a miss): blue; by ours only (too
much, e.g. spray the true surface does not have): green; neither: grey.
"""
import os
import sys
import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_aovs import angle_deg, load_coverage_and_normals  # noqa: E402


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    ref, cand, out = sys.argv[1:4]
    top = float(sys.argv[4]) if len(sys.argv) == 5 else 45.0
    ar = np.nan_to_num(np.load(ref + '_A.npy').astype(np.float64)) > 0.5
    nr = np.load(ref + '_N.npy').astype(np.float64)
    ac, nc = load_coverage_and_normals(cand)
    ac = np.nan_to_num(ac) > 0.5
    ang = angle_deg(nr, nc)
    t = np.clip(np.nan_to_num(ang, nan=top) / top, 0.0, 1.0)
    # black -> red -> yellow -> white ("hot")
    hot = np.stack([np.clip(3 * t, 0, 1), np.clip(3 * t - 1, 0, 1), np.clip(3 * t - 2, 0, 1)], -1)
    img = np.full(ar.shape + (3,), 0.5)
    both = ar & ac
    img[both] = hot[both]
    img[ar & ~ac] = (0.2, 0.4, 1.0)
    img[ac & ~ar] = (0.2, 0.8, 0.2)
    o = oiio.ImageOutput.create(out)
    if o is None:
        sys.exit('error_map.py: %s' % oiio.geterror())
    o.open(out, oiio.ImageSpec(img.shape[1], img.shape[0], 3, oiio.UINT8))
    o.write_image((img * 255.0 + 0.5).astype(np.uint8))
    o.close()


if __name__ == '__main__':
    main()
