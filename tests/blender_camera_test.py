"""examples/blender_camera.py run headless inside Blender (docs/compositing.md).

A camera is placed in Blender's factory scene at a known eye, looking at a
known point without roll, with a 50 mm lens on a 36 mm sensor and a 16:9
picture; the script's scene file must give that eye, a target on the view
axis and the vertical field of view 2 atan(18 / 50 * 9 / 16); a rolled
camera is refused. Skipped (exit 77, ctest's SKIP_RETURN_CODE) where
Blender is not installed.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "blender_camera.py")
blender = shutil.which("blender")
if not blender:
    print("blender not installed: skipped")
    sys.exit(77)

SETUP = """
import bpy, mathutils
scene = bpy.context.scene
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 1920, 1080, 50
cam = scene.camera
cam.data.lens, cam.data.sensor_width, cam.data.sensor_fit = 50.0, 36.0, 'AUTO'
cam.location = (4.0, -3.0, 2.0)
direction = mathutils.Vector((1.0, 1.0, 0.5)) - cam.location
cam.rotation_euler = direction.to_track_quat('-Z', 'Y').to_euler()
cam.rotation_euler.rotate_axis('Z', {roll})
"""


def run(out, roll):
    command = [blender, "-b", "--factory-startup", "--python-exit-code", "2", "--python-expr", SETUP.format(roll=roll),
               "--python", SCRIPT, "--", out, "--particles", "f.bgeo"]
    return subprocess.run(command, capture_output=True, text=True, timeout=300)


with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "scene.json")
    r = run(out, 0.0)
    if r.returncode != 0:
        sys.exit("blender_camera.py failed:\n" + r.stdout + r.stderr)
    with open(out) as f:
        scene = json.load(f)
    cam = scene["camera"]
    assert scene["width"] == 960 and scene["height"] == 540, scene
    assert scene["particles"] == "f.bgeo", scene
    assert cam["up"] == [0.0, 0.0, 1.0], cam
    assert all(abs(a - b) < 1e-5 for a, b in zip(cam["eye"], (4.0, -3.0, 2.0))), cam
    axis = [t - e for t, e in zip(cam["target"], cam["eye"])]
    want = [1.0 - 4.0, 1.0 + 3.0, 0.5 - 2.0]
    norm = math.sqrt(sum(w * w for w in want))
    assert all(abs(a - w / norm) < 1e-5 for a, w in zip(axis, want)), (axis, want)
    fov = math.degrees(2.0 * math.atan(18.0 / 50.0 * 9.0 / 16.0))
    assert abs(cam["fov"] - fov) < 1e-4, (cam["fov"], fov)
    rolled = run(os.path.join(tmp, "rolled.json"), 0.3)
    assert rolled.returncode != 0 and "rolled" in rolled.stdout + rolled.stderr, rolled.stdout + rolled.stderr
print("blender_camera.py: camera and field of view as Blender's")
