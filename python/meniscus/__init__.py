"""Meniscus: SPH particle fluids to liquid images, meshes and simulations.

    import meniscus
    frame = meniscus.read("ParticleData_Fluid_21.bgeo")   # dict of numpy arrays
    image = meniscus.render(frame, width=640, height=360)  # H x W x 4 uint8
    meniscus.write_png("frame.png", image, alpha=False)    # what `meniscus render` writes

The C++ library does the work (the extension module meniscus._meniscus);
render() takes `meniscus render`'s options as keywords (noise=True,
filter="curvature-flow", fill_holes=0, ...; meniscus.settings() lists them),
so a render matches the CLI's PNG for the same options byte for byte.

Errors: ValueError for bad arguments and arrays (shape, dtype, layout,
non-finite positions), TypeError for an unknown keyword, OSError
(FileNotFoundError) for particle files that cannot be read or written,
RuntimeError when the pipeline fails while running (e.g. backend="gl"
without a GL context).
"""

import os as _os
import sys as _sys
import warnings as _warnings

import numpy as _np

from ._meniscus import (
    DEMO_RADIUS,
    Renderer,
    Simulation,
    __version__,
    auto_camera,
    demo,
    estimate_radius,
    mesh,
    read,
    sequence,
    settings,
    simulate,
    write_mesh,
    write_png,
)

__all__ = [
    "DEMO_RADIUS",
    "Renderer",
    "Simulation",
    "auto_camera",
    "demo",
    "estimate_radius",
    "mesh",
    "read",
    "render",
    "sequence",
    "settings",
    "simulate",
    "write_mesh",
    "write_png",
]


def render(particles, radius=None, *, width=None, height=None, camera=None, filter=None, backend="auto",
           aovs=False, velocity=None, density=None, id=None, fluid=None, color=None, radii=None, studio=None,
           frame=0, **settings):
    """Render one frame of particles; returns the 8-bit sRGB image, H x W x 4 uint8.

    particles: N x 3 positions (float32 used in place, float64 converted
    once; C-contiguous) or a dict as read() returns it (its velocity,
    density, id, fluid, color and radius arrays are used as the CLI uses a
    file's).
    radius: the particle radius in metres; None estimates it as the CLI does.
    width, height: pixels (None: the library's default, 1280 x 720). camera: None (the CLI's automatic view) or a dict
    {'eye': (x, y, z), 'target': (x, y, z), 'fov': 40, 'near': .., 'far': ..}
    (auto_camera() returns one). filter: the smoothing filter by its CLI
    name ('narrow-range', 'curvature-flow', 'bilateral', ...; None: the
    default). backend: 'cpu', 'gl' or 'auto' (as the CLI's --backend).
    aovs: also return a dict of float32 AOV images (color, depth, raw_depth,
    normal, thickness, ...): (image, aovs).
    background: (rgb, depth) numpy arrays of another renderer's picture of the
    set, made by this camera (Renderer.render; docs/compositing.md); its size
    is the picture's unless width and height are given. A string is the
    studio setting instead ('studio', 'floor', 'none').
    settings: any `meniscus render` option by its Python name (noise=True,
    noise_bump=0.3, material='lava', fill_holes=0, anisotropy='off', up=(0, 0, 1),
    view='depth', ...); meniscus.settings() lists them.

    One frame through a fresh Renderer(width, height, backend, **settings);
    see Renderer.render for the other arguments. The GIL is released while
    it renders.
    """
    if filter is not None:
        settings["filter"] = filter
    # background=(rgb, depth): a picture to composite into (Renderer.render);
    # a string is the studio setting ('studio', 'floor', 'none', 'auto').
    backdrop = None
    if "background" in settings and not isinstance(settings["background"], str):
        backdrop = settings.pop("background")
        if width is None and height is None:
            height, width = (int(n) for n in _np.shape(backdrop[1])[:2])
    size = {k: v for k, v in (("width", width), ("height", height)) if v is not None}
    r = Renderer(backend=backend, **size, **settings)
    return r.render(particles, radius=radius, camera=camera, aovs=aovs, velocity=velocity, density=density,
                    id=id, fluid=fluid, color=color, radii=radii, studio=studio, frame=frame, background=backdrop)


def _warn(message):
    """A UserWarning at the caller's line outside this package (the C++ functions call it)."""
    level, frame = 2, _sys._getframe(1)
    here = _os.path.dirname(_os.path.abspath(__file__))
    while frame is not None and _os.path.dirname(_os.path.abspath(frame.f_code.co_filename)) == here:
        frame, level = frame.f_back, level + 1
    _warnings.warn(message, UserWarning, stacklevel=level)
