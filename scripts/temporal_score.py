#!/usr/bin/python3
"""Temporal coherence of a rendered sequence against the true surface.

  temporal_score.py REF_PREFIX_0 CAND_0.exr REF_PREFIX_1 CAND_1.exr [...]

Frames in order, each as refsurf's --out prefix (PREFIX_A/_Z/_N.npy) and our EXR
(channels A, N.X, N.Y, N.Z), all from one static camera. For each pair of
consecutive frames, over the pixels covered in all four images: the angle
between our normals at t and t+1 (how much our surface turns), the same for the
true surface, and the per-pixel excess |ours - true|. Prints one line per pair
and the means over all pairs, in degrees. A pipeline that flickers (noise,
order-dependent ties) turns more than the surface does: excess >> 0.
"""
import os
import sys
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_aovs import angle_deg as angle, load_coverage_and_normals as load_exr  # noqa: E402


def load_ref(prefix):
    a = np.load(prefix + '_A.npy').astype(np.float64)
    n = np.load(prefix + '_N.npy').astype(np.float64)
    return a, n


def main():
    args = sys.argv[1:]
    if len(args) < 4 or len(args) % 2 or args[0] in ('-h', '--help'):
        sys.exit(__doc__)
    frames = [(load_ref(args[i]), load_exr(args[i + 1])) for i in range(0, len(args), 2)]
    ours_all, true_all, excess_all = [], [], []
    for k in range(len(frames) - 1):
        (ar0, nr0), (ac0, nc0) = frames[k]
        (ar1, nr1), (ac1, nc1) = frames[k + 1]
        m = (np.nan_to_num(ar0) > 0.5) & (np.nan_to_num(ar1) > 0.5) & (np.nan_to_num(ac0) > 0.5) & (np.nan_to_num(ac1) > 0.5)
        for n in (nr0, nr1, nc0, nc1):
            m &= np.isfinite(n).all(-1) & (np.abs(n).sum(-1) > 0)
        ours = angle(nc0[m], nc1[m])
        true = angle(nr0[m], nr1[m])
        excess = np.abs(ours - true)
        ours_all.append(ours), true_all.append(true), excess_all.append(excess)
        print('frames %d-%d: %d px, our change %.2f deg, true change %.2f deg, |difference| %.2f deg (median %.2f)'
              % (k, k + 1, m.sum(), ours.mean(), true.mean(), excess.mean(), np.median(excess)))
    o, t, e = (np.concatenate(x) for x in (ours_all, true_all, excess_all))
    print('all pairs: our change %.2f deg, true change %.2f deg, |difference| %.2f deg (median %.2f, p90 %.2f)'
          % (o.mean(), t.mean(), e.mean(), np.median(e), np.percentile(e, 90)))


if __name__ == '__main__':
    main()
