# %% [markdown]
# # Meniscus from Python
#
# A notebook-style script (cells marked `# %%`, as VS Code, Spyder and Jupytext
# read them): read a SPlisHSPlasH frame, render it, look at its AOVs, render a
# short sequence with one camera, mesh it, and run a small simulation. Needs
# only numpy and the `meniscus` module (`PYTHONPATH=build/python`, see
# docs/python.md). The ctest test `python.example` runs it whole.
#
#     PYTHONPATH=build/python python3 examples/python_render.py --out /tmp/meniscus_example

# %%
import argparse
import os
import time

import numpy as np

import meniscus

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--out", default="meniscus_example", help="folder for the images and the mesh")
args, _ = parser.parse_known_args()  # parse_known_args: a notebook kernel passes its own
os.makedirs(args.out, exist_ok=True)
print("meniscus", meniscus.__version__, "->", os.path.abspath(args.out))

# %% [markdown]
# ## Read a frame
# `read()` gives a dict of numpy arrays: `position` (N x 3 float32) and the
# file's attributes under their canonical names.

# %%
frame_path = os.path.join(ROOT, "data", "demo", "ParticleData_Fluid_21.bgeo")
frame = meniscus.read(frame_path)
p = frame["position"]
print(f"{len(p)} particles, bounds {p.min(axis=0)} .. {p.max(axis=0)} m")
print("attributes:", {k: (v.dtype.name, v.shape[1:]) for k, v in frame.items() if k != "position"})
radius = meniscus.estimate_radius(frame)
print(f"estimated radius {radius:.4f} m (the simulation used {meniscus.DEMO_RADIUS} m)")

# %% [markdown]
# ## Render it
# The keywords are `meniscus render`'s options (`meniscus.settings()` lists
# them); the image is what the CLI writes for the same options.

# %%
t = time.perf_counter()
image = meniscus.render(frame, radius=meniscus.DEMO_RADIUS, width=480, height=270, backend="cpu")
print(f"rendered {image.shape} {image.dtype} in {time.perf_counter() - t:.2f} s")
meniscus.write_png(os.path.join(args.out, "frame21.png"), image, alpha=False)

# The same particles as lava, with surface noise and foam, seen from the other side.
lava = meniscus.render(frame, radius=meniscus.DEMO_RADIUS, width=480, height=270, backend="cpu",
                       material="lava", noise=True, azimuth=-50)
meniscus.write_png(os.path.join(args.out, "frame21_lava.png"), lava, alpha=False)

# %% [markdown]
# ## AOVs
# With `aovs=True` the float images come too: linear colour, eye depth,
# normals, thickness... Here the depth as a grey image (near = white).

# %%
image, aovs = meniscus.render(p, radius=meniscus.DEMO_RADIUS, width=480, height=270, backend="cpu", aovs=True)
print("AOVs:", {k: v.shape for k, v in aovs.items()})
depth = aovs["depth"]
liquid = np.isfinite(depth)
near, far = depth[liquid].min(), depth[liquid].max()
grey = np.zeros(depth.shape, np.uint8)
grey[liquid] = (255 * (far - depth[liquid]) / max(far - near, 1e-6)).astype(np.uint8)
meniscus.write_png(os.path.join(args.out, "frame21_depth.png"), np.dstack([grey, grey, grey]))
print(f"liquid covers {liquid.mean():.0%} of the image, {near:.2f} to {far:.2f} m away; "
      f"thickest {aovs['thickness'].max():.3f} m")

# %% [markdown]
# ## A sequence, one camera
# A `Renderer` keeps its backend and caches between frames. For a steady shot
# fix the camera and the studio on the first frame (the CLI does the same).

# %%
files = meniscus.sequence(os.path.join(ROOT, "data", "demo", "ParticleData_Fluid_*.bgeo"))[:3]
first = meniscus.read(files[0])
camera = meniscus.auto_camera(first, radius=meniscus.DEMO_RADIUS, width=320, height=180)
studio = (first["position"].min(axis=0), first["position"].max(axis=0))
renderer = meniscus.Renderer(320, 180, backend="cpu", noise=True)
for i, path in enumerate(files):
    img = renderer.render(meniscus.read(path), radius=meniscus.DEMO_RADIUS, camera=camera, studio=studio, frame=i)
    meniscus.write_png(os.path.join(args.out, "seq_%02d.png" % i), img, alpha=False)
print(f"{len(files)} frames on {renderer.backend}, camera at {np.round(camera['eye'], 2)}")

# %% [markdown]
# ## Mesh it
# The isosurface as vertices, triangles and normals; written as OBJ by hand.

# %%
vertices, faces, normals = meniscus.mesh(frame, radius=meniscus.DEMO_RADIUS, cube_size=1.0)  # cubes of r
print(f"mesh: {len(vertices)} vertices, {len(faces)} triangles")
with open(os.path.join(args.out, "frame21.obj"), "w") as f:
    np.savetxt(f, vertices, fmt="v %.6f %.6f %.6f")
    np.savetxt(f, normals, fmt="vn %.6f %.6f %.6f")
    np.savetxt(f, np.repeat(faces + 1, 2, axis=1), fmt="f %d//%d %d//%d %d//%d")

# %% [markdown]
# ## Simulate
# A coarse version of `scenes/drop.json` (r = 2 cm, 0.2 s); each frame is a dict
# like read()'s, so it renders the same way.

# %%
sim = meniscus.simulate(os.path.join(ROOT, "scenes", "drop.json"), duration=0.2, radius=0.02)
print(f"simulating {sim.particles} particles, {len(sim)} frames")
for f in sim:
    print(f"  t = {f['time']:.2f} s: lowest particle at y = {f['position'][:, 1].min():.3f} m, "
          f"fastest {np.linalg.norm(f['velocity'], axis=1).max():.2f} m/s")
img = meniscus.render(f, radius=sim.radius, width=320, height=180, backend="cpu", studio=sim.domain)
meniscus.write_png(os.path.join(args.out, "drop_last.png"), img, alpha=False)
print("done")
