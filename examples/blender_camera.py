"""Writes a Blender scene's active camera in Meniscus's camera format.

Run headless inside Blender (Blender 3.0 or later):

    blender -b set.blend --python examples/blender_camera.py -- scene.json \
        --particles 'out/*.bgeo' --backdrop set.exr
    blender -b set.blend --python examples/blender_camera.py -- path.json --path

The first writes a render scene file (`meniscus render scene.json -o out.png`):
the camera at the current frame ("camera": eye, target, fov), the picture's
size, and, when given, the particles and the backdrop (the set's colour and
its Z pass rendered by Blender from the same camera, an OpenEXR with R, G, B
and Z; --backdrop-depth-kind blender; docs/compositing.md). With --path it
writes the camera at every frame from the scene's start to its end as a
camera path (`meniscus render ... --camera-path path.json`): one key a frame,
its time (frame - start) / fps seconds, so a movie at the scene's frame rate
(--fps) sees the set as Blender's frames did.

Coordinates: the camera is written in the particles' coordinates. By default
those are Blender's own (z up: give `--up 0,0,1` to meniscus). With
--particles-up y the particles are y-up data that was turned into Blender's
z-up frame on import (Blender's importers map a file's (x, y, z) to
(x, -z, y)); the camera is turned back, so meniscus's default up (+y) fits.

What Meniscus's camera cannot hold is refused with a message: a roll about
the view axis (its camera's up is the data's up), lens shift, an orthographic
or panoramic camera, non-square pixels.
"""
import argparse
import json
import math
import sys

try:
    import bpy
    from mathutils import Vector
except ImportError:  # outside Blender
    sys.exit("blender_camera.py runs inside Blender: blender -b FILE.blend --python blender_camera.py -- OUT.json")


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender_camera.py", description=__doc__.splitlines()[0])
    p.add_argument("output", help="the JSON file to write")
    p.add_argument("--path", action="store_true", help="every frame, as a camera path (--camera-path)")
    p.add_argument("--particles-up", choices=["z", "y"], default="z",
                   help="the particles' up axis: z (Blender's own coordinates) or y (turned on import)")
    p.add_argument("--particles", help="the scene file's particles (a file, folder or pattern)")
    p.add_argument("--backdrop", help="the scene file's backdrop (an OpenEXR with R, G, B and Z)")
    return p.parse_args(argv)


def to_particles(v, up):
    """A Blender world point in the particles' coordinates."""
    return [v.x, v.z, -v.y] if up == "y" else [v.x, v.y, v.z]


def vertical_fov_degrees(scene, data):
    """The full vertical field of view of the rendered picture, degrees."""
    r = scene.render
    width = r.resolution_x * r.pixel_aspect_x
    height = r.resolution_y * r.pixel_aspect_y
    fit = data.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if width >= height else "VERTICAL"
    if fit == "HORIZONTAL":
        half_width = data.sensor_width / (2.0 * data.lens)
        return math.degrees(2.0 * math.atan(half_width * height / width))
    return math.degrees(2.0 * math.atan(data.sensor_height / (2.0 * data.lens)))


def camera_at(scene, camera, up):
    """The camera now: eye, target (1 m ahead on the view axis) and field of view."""
    data = camera.data
    if data.type != "PERSP":
        sys.exit("blender_camera.py: the camera '%s' is %s; Meniscus's camera is a perspective pinhole"
                 % (camera.name, data.type.lower()))
    if abs(data.shift_x) > 1e-6 or abs(data.shift_y) > 1e-6:
        sys.exit("blender_camera.py: the camera '%s' has a lens shift, which Meniscus's camera cannot hold"
                 % camera.name)
    if abs(scene.render.pixel_aspect_x - scene.render.pixel_aspect_y) > 1e-6:
        sys.exit("blender_camera.py: the pixels are not square (render pixel aspect)")
    m = camera.matrix_world
    eye = m.to_translation()
    forward = (m.to_3x3() @ Vector((0.0, 0.0, -1.0))).normalized()
    cam_up = (m.to_3x3() @ Vector((0.0, 1.0, 0.0))).normalized()
    world_up = Vector((0.0, 0.0, 1.0))
    # No roll: the camera's up lies in the plane of the view axis and the world's up.
    expected = (world_up - forward * forward.dot(world_up))
    if expected.length > 1e-6 and cam_up.dot(expected.normalized()) < math.cos(math.radians(0.1)):
        sys.exit("blender_camera.py: the camera '%s' is rolled about its view axis at frame %d; Meniscus's "
                 "camera keeps the data's up (remove the roll)" % (camera.name, scene.frame_current))
    return {
        "eye": to_particles(eye, up),
        "target": to_particles(eye + forward, up),
        "fov": vertical_fov_degrees(scene, data),
    }


def main():
    args = arguments()
    scene = bpy.context.scene
    camera = scene.camera
    if camera is None:
        sys.exit("blender_camera.py: the scene has no active camera")
    fps = scene.render.fps / scene.render.fps_base
    # The camera's world matrix as the scene now places it (a script before
    # this one may have moved it: Blender updates matrix_world lazily).
    bpy.context.view_layer.update()
    if args.path:
        out = []
        for frame in range(scene.frame_start, scene.frame_end + 1):
            scene.frame_set(frame)
            key = camera_at(scene, camera, args.particles_up)
            key["time"] = (frame - scene.frame_start) / fps
            out.append(key)
    else:
        out = {"camera": camera_at(scene, camera, args.particles_up)}
        if args.particles_up == "z":
            out["camera"]["up"] = [0.0, 0.0, 1.0]
        r = scene.render
        out["width"] = int(r.resolution_x * r.resolution_percentage / 100)
        out["height"] = int(r.resolution_y * r.resolution_percentage / 100)
        if args.particles:
            out["particles"] = args.particles
        if args.backdrop:
            out["backdrop"] = args.backdrop
            out["backdrop_depth_kind"] = "blender"
    with open(args.output, "w") as f:
        json.dump(out, f, indent=1)
    print("blender_camera.py: wrote", args.output)


main()
