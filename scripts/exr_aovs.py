"""Reads the coverage and normals of a meniscus EXR (channels A, N.X, N.Y, N.Z)
with OpenImageIO, for scripts/temporal_score.py and scripts/error_map.py."""
import sys
import numpy as np


def load_coverage_and_normals(path):
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit('%s: %s' % (path, oiio.geterror()))
    spec = inp.spec()
    px = np.asarray(inp.read_image(0, 0, 0, spec.nchannels, oiio.FLOAT), np.float64)
    inp.close()
    px = px.reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    for c in ('A', 'N.X', 'N.Y', 'N.Z'):
        if c not in names:
            sys.exit('%s: no channel %s (has %s)' % (path, c, names))
    ch = lambda c: px[..., names.index(c)]
    return ch('A'), np.stack([ch('N.X'), ch('N.Y'), ch('N.Z')], -1)


def angle_deg(a, b):
    """Angle between normals, exact near 0 (atan2 of |a x b| and a . b)."""
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), (a * b).sum(-1)))
