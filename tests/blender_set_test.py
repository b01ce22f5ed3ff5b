"""From Blender to a composite, run headless (docs/compositing.md, "From Blender").

examples/blender_set.py builds and renders the dam break's tank in Blender
(Cycles, its colour and Z pass in a multilayer OpenEXR, and the colour as an
8-bit PNG); examples/blender_camera.py writes its camera in Meniscus's format;
`meniscus render` composites frame 21 of the dam break into the set. Checked
on the pictures: around the liquid the composite is Blender's own picture
(within 3 codes of its PNG), the liquid is seen in the tank, and where the
pillar in front of the tank stands (projected with the exported camera) the
pillar hides the liquid. The same for a camera turning over three frames:
the camera path (blender_camera.py --path) and the backdrop sequence
(--backdrop 'turn_####.exr'), each frame against its own picture. A wrong
camera, field of view, up axis, depth convention or frame of the sequence
puts the liquid over the pillar or outside the tank. Skipped
(exit 77, ctest's SKIP_RETURN_CODE) where Blender is not installed.

Usage: blender_set_test.py MENISCUS_EXECUTABLE
"""
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
FRAME = os.path.join(ROOT, "data", "dambreak_r0.01", "ParticleData_Fluid_21.bgeo")
W, H = 160, 90

blender = shutil.which("blender")
if not blender:
    print("blender not installed: skipped")
    sys.exit(77)
meniscus = sys.argv[1]


def run(command):
    r = subprocess.run(command, capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        sys.exit("failed: %s\n%s%s" % (" ".join(command), r.stdout, r.stderr))


def read_png(path):
    """An 8-bit RGB or RGBA, non-interlaced PNG: rows of (r, g, b) tuples, top first."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour in (2, 6) and interlace == 0, (path, depth, colour, interlace)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = previous[i], previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return rows


def project(camera, point):
    """Pixel (column, row; row 0 at the top) of a point seen by a scene file's camera (up +y)."""
    eye, target = camera["eye"], camera["target"]
    sub = lambda a, b: [a[i] - b[i] for i in range(3)]
    dot = lambda a, b: sum(a[i] * b[i] for i in range(3))
    cross = lambda a, b: [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    unit = lambda a: [v / math.sqrt(dot(a, a)) for v in a]
    forward = unit(sub(target, eye))
    right = unit(cross(forward, [0.0, 1.0, 0.0]))
    up = cross(right, forward)
    d = sub(point, eye)
    focal = (H / 2.0) / math.tan(math.radians(camera["fov"]) / 2.0)
    return (W / 2.0 + focal * dot(d, right) / dot(d, forward), H / 2.0 - focal * dot(d, up) / dot(d, forward))


def check(set_png, composite_png, camera, what):
    """The composite against Blender's own picture of the set, seen by `camera`."""
    blender_rows, composite_rows = read_png(set_png), read_png(composite_png)

    def difference(x, y):
        return max(abs(a - b) for a, b in zip(blender_rows[y][x], composite_rows[y][x]))

    diffs = [difference(x, y) for y in range(H) for x in range(W)]
    kept = sum(d <= 3 for d in diffs) / len(diffs)
    liquid = sum(d > 12 for d in diffs) / len(diffs)
    # The pillar (examples/blender_set.py: radius 0.09 m at data x = -0.55,
    # z = 1.2, in front of the tank): its axis's pixels at the liquid's
    # heights show the pillar, and the liquid is seen just beside it.
    hidden = beside = 0
    for height in (0.45, 0.55, 0.65, 0.75):  # (lower, the rim in front of the tank is behind it)
        x, y = project(camera, [-0.55, height, 1.2])
        column, row = int(x), int(y)
        hidden += difference(column, row) <= 3
        beside += max(difference(column + k, row) for k in (-6, -5, 5, 6)) > 12
    print("%s: Blender's own picture kept on %.1f%% of the pixels, the liquid on %.1f%%; the pillar hides the liquid "
          "at %d of 4 heights, the liquid seen beside it at %d" % (what, 100 * kept, 100 * liquid, hidden, beside))
    assert kept > 0.5, (what, kept)
    assert liquid > 0.04, (what, liquid)
    assert hidden == 4, (what, hidden)
    assert beside == 4, (what, beside)


with tempfile.TemporaryDirectory() as tmp:
    at = lambda name: os.path.join(tmp, name)
    set_script, camera_script = (os.path.join(ROOT, "examples", n) for n in ("blender_set.py", "blender_camera.py"))
    size = ["--width", str(W), "--height", str(H), "--samples", "4"]
    # A still: the set, its camera as a render scene file, the composite.
    run([blender, "-b", "--factory-startup", "--python-exit-code", "2", "--python", set_script, "--", at("set.exr"),
         "--blend", at("set.blend"), "--png", at("set.png")] + size)
    run([blender, "-b", at("set.blend"), "--python-exit-code", "2", "--python", camera_script, "--", at("scene.json"),
         "--particles-up", "y", "--particles", FRAME, "--backdrop", at("set.exr")])
    with open(at("scene.json")) as f:
        scene = json.load(f)
    assert scene["width"] == W and scene["height"] == H, scene
    run([meniscus, "render", at("scene.json"), "-o", at("composite.png")])
    check(at("set.png"), at("composite.png"), scene["camera"], "still")
    # A moving camera: three frames of the set turning 30 degrees, the camera
    # path, and the backdrop sequence, each frame over its own picture.
    run([blender, "-b", "--factory-startup", "--python-exit-code", "2", "--python", set_script, "--",
         at("turn_####.exr"), "--blend", at("turn.blend"), "--png", at("turn_####.png"), "--frames", "3", "--fps", "15",
         "--orbit", "30"] + size)
    run([blender, "-b", at("turn.blend"), "--python-exit-code", "2", "--python", camera_script, "--", at("path.json"),
         "--particles-up", "y", "--path"])
    with open(at("path.json")) as f:
        path = json.load(f)
    assert len(path) == 3 and abs(path[2]["time"] - 2.0 / 15.0) < 1e-9, path
    run([meniscus, "render", FRAME, "--frames", "3", "--fps", "15", "--width", str(W), "--height", str(H),
         "--camera-path", at("path.json"), "--backdrop", at("turn_####.exr"), "--backdrop-depth-kind", "blender",
         "-o", at("turn_%d.png")])
    for k in range(3):
        check(at("turn_%04d.png" % (k + 1)), at("turn_%d.png" % k), path[k], "moving camera, frame %d" % (k + 1))
    assert read_png(at("turn_0001.png")) != read_png(at("turn_0003.png"))  # the set seen from elsewhere
print("blender_set.py: the set composited with the liquid as Blender rendered it, still and moving")
