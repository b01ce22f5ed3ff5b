"""Builds and renders a small set for the dam break in Blender: its tank.

Run headless inside Blender (3.0 or later), from the factory scene:

    blender -b --factory-startup --python examples/blender_set.py -- set.exr \
        --blend set.blend --png set.png --width 960 --height 540 --samples 64
    blender -b --factory-startup --python examples/blender_set.py -- set_####.exr \
        --blend set.blend --frames 61 --fps 15 --orbit 30

The set is the tank of SPlisHSPlasH's dam break scene (a 4 x 3 x 1.5 m box,
its floor at height 0, the liquid's data y-up, so Blender's (x, y, z) is the
data's (x, -z, y)): a tiled floor and back wall, plain side walls, the front
wall cut down to a low rim, a pillar in front of the tank, a sun and a sky.
Cycles renders it from the scene's camera into `set.exr`, an OpenEXR
(multilayer, 32-bit float) with the Combined colour (linear) and the Z pass
(planar eye depth, metres) that `meniscus render --backdrop set.exr
--backdrop-depth-kind blender` composites the liquid into
(docs/compositing.md). --blend saves the set for examples/blender_camera.py,
which writes the camera in Meniscus's format (--particles-up y); --png also
writes the Combined colour as 8-bit sRGB (the Standard view, no dither).

With --frames N the camera moves: it turns --orbit degrees about the vertical
through the point it looks at, over frames 1 to N at --fps frames per second
(a Track To constraint keeps it level, without roll), and each frame is
rendered to the output's name with its last run of '#' replaced by the frame
number (set_0001.exr, ...): the backdrop sequence of `meniscus render
--backdrop 'set_####.exr'`, with the camera path examples/blender_camera.py
--path writes from the saved set.
"""
import argparse
import math
import sys

try:
    import bpy
    from mathutils import Vector
except ImportError:  # outside Blender
    sys.exit("blender_set.py runs inside Blender: blender -b --factory-startup --python blender_set.py -- OUT.exr")

# The tank (data coordinates, metres): x in [-2, 2], z in [-0.75, 0.75], the
# floor at y = 0 (SPlisHSPlasH's DamBreakModel.json: UnitBox scaled 4 x 3 x 1.5).
HALF_X, HALF_Z = 2.0, 0.75
WALL = 0.08          # wall thickness, metres
WALL_HEIGHT = 1.3    # the walls' height shown, metres (the tank's 3 m would hide the view)
RIM_HEIGHT = 0.18    # the front wall cut down to this, metres


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender_set.py", description=__doc__.splitlines()[0])
    p.add_argument("output", help="the OpenEXR to render (Combined and Z)")
    p.add_argument("--blend", help="also save the set as this .blend")
    p.add_argument("--png", help="also save the Combined colour as this 8-bit sRGB PNG")
    p.add_argument("--width", type=int, default=960, help="pixels")
    p.add_argument("--height", type=int, default=540, help="pixels")
    p.add_argument("--samples", type=int, default=64, help="Cycles samples per pixel")
    p.add_argument("--frames", type=int, default=1, help="frames of a moving camera (1: a still)")
    p.add_argument("--fps", type=float, default=24.0, help="the animation's frames per second")
    p.add_argument("--orbit", type=float, default=20.0, help="degrees the camera turns over the frames")
    args = p.parse_args(argv)
    if args.frames > 1 and "#" not in args.output:
        p.error("--frames %d: the output's name needs a run of # for the frame number (set_####.exr)" % args.frames)
    return args


def frame_name(pattern, number):
    """`pattern` with its last run of '#' replaced by `number`, zero-padded to the run's length."""
    last = pattern.rfind("#")
    if last < 0:
        return pattern
    first = last
    while first > 0 and pattern[first - 1] == "#":
        first -= 1
    return pattern[:first] + str(number).zfill(last + 1 - first) + pattern[last + 1:]


def blender_point(x, y, z):
    """A data point (y up) in Blender's coordinates (z up)."""
    return Vector((x, -z, y))


def material(name, base, pattern=None, roughness=0.6, scale=4.0):
    """A Principled BSDF of colour `base`, or of a checker or brick pattern of it."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    if pattern:
        coords = nodes.new("ShaderNodeTexCoord")
        tex = nodes.new("ShaderNodeTexChecker" if pattern == "checker" else "ShaderNodeTexBrick")
        tex.inputs["Scale"].default_value = scale
        tex.inputs["Color1"].default_value = (*base, 1.0)
        tex.inputs["Color2"].default_value = (*[0.35 * c for c in base], 1.0)
        if pattern == "brick":
            tex.inputs["Mortar"].default_value = (0.5, 0.5, 0.48, 1.0)
        # A wall stands in Blender's x-z plane: its pattern on (x, z).
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = (math.radians(90.0) if pattern == "brick" else 0.0, 0.0, 0.0)
        links.new(coords.outputs["Object"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return m


def box(name, lo, hi, mat):
    """An axis-aligned box between two data points."""
    a, b = blender_point(*lo), blender_point(*hi)
    centre = (a + b) / 2.0
    size = Vector((abs(b.x - a.x), abs(b.y - a.y), abs(b.z - a.z)))
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=centre)
    o = bpy.context.active_object
    o.name = name
    o.scale = size
    bpy.ops.object.transform_apply(scale=True)
    o.data.materials.append(mat)
    return o


def build_set():
    # The factory scene's cube and light go; its camera stays and is placed.
    for o in list(bpy.data.objects):
        if o.type != "CAMERA":
            bpy.data.objects.remove(o, do_unlink=True)
    tiles = material("Tiles", (0.55, 0.5, 0.42), "checker", 0.5, 8.0)
    bricks = material("Bricks", (0.5, 0.22, 0.15), "brick", 0.8, 1.5)
    concrete = material("Concrete", (0.45, 0.45, 0.47), None, 0.9)
    ground = material("Ground", (0.25, 0.3, 0.2), "checker", 0.9, 3.0)
    # The ground around the tank, just under its floor.
    bpy.ops.mesh.primitive_plane_add(size=30.0, location=blender_point(0.0, -0.01, 0.0))
    bpy.context.active_object.data.materials.append(ground)
    box("Floor", (-HALF_X, -0.005, -HALF_Z), (HALF_X, 0.0, HALF_Z), tiles)
    box("BackWall", (-HALF_X - WALL, 0.0, -HALF_Z - WALL), (HALF_X + WALL, WALL_HEIGHT, -HALF_Z), bricks)
    box("LeftWall", (-HALF_X - WALL, 0.0, -HALF_Z), (-HALF_X, WALL_HEIGHT, HALF_Z + WALL), concrete)
    box("RightWall", (HALF_X, 0.0, -HALF_Z), (HALF_X + WALL, WALL_HEIGHT, HALF_Z + WALL), concrete)
    box("FrontRim", (-HALF_X, 0.0, HALF_Z), (HALF_X, RIM_HEIGHT, HALF_Z + WALL), concrete)
    # A pillar in front of the tank: it hides part of the liquid.
    bpy.ops.mesh.primitive_cylinder_add(radius=0.09, depth=1.6, location=blender_point(-0.55, 0.8, HALF_Z + 0.45))
    bpy.context.active_object.name = "Pillar"
    bpy.context.active_object.data.materials.append(concrete)
    # A sun and a plain sky.
    bpy.ops.object.light_add(type="SUN", rotation=(math.radians(40.0), math.radians(15.0), math.radians(-30.0)))
    bpy.context.active_object.data.energy = 2.0
    world = bpy.context.scene.world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.45, 0.6, 0.85, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6


def place_camera(scene, args):
    cam = scene.camera
    eye, target = blender_point(0.9, 2.3, 4.9), blender_point(-0.35, 0.25, 0.0)
    cam.data.lens, cam.data.sensor_width, cam.data.sensor_fit = 32.0, 36.0, "AUTO"
    cam.data.clip_start, cam.data.clip_end = 0.05, 100.0
    if args.frames <= 1:
        cam.location = eye
        cam.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()  # no roll
        return
    # Aimed at an empty at the target by a Track To constraint (level: its up
    # is the world's), the eye keyed at every frame on the circle about the
    # vertical through the target.
    bpy.ops.object.empty_add(location=target)
    aim = bpy.context.active_object
    aim.name = "CameraTarget"
    track = cam.constraints.new("TRACK_TO")
    track.target, track.track_axis, track.up_axis = aim, "TRACK_NEGATIVE_Z", "UP_Y"
    cam.rotation_euler = (0.0, 0.0, 0.0)
    scene.frame_start, scene.frame_end = 1, args.frames
    scene.render.fps = max(1, round(args.fps))
    scene.render.fps_base = scene.render.fps / args.fps
    offset = eye - target
    for frame in range(1, args.frames + 1):
        turn = math.radians(args.orbit) * (frame - 1) / (args.frames - 1)
        c, s = math.cos(turn), math.sin(turn)
        cam.location = target + Vector((c * offset.x - s * offset.y, s * offset.x + c * offset.y, offset.z))
        cam.keyframe_insert("location", frame=frame)


def configure(scene, args):
    """The render settings, saved with the set: its size is the camera's picture."""
    r = scene.render
    r.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False
    r.resolution_x, r.resolution_y, r.resolution_percentage = args.width, args.height, 100
    r.dither_intensity = 0.0
    r.film_transparent = False
    scene.view_settings.view_transform = "Standard"  # the Combined is linear in the EXR either way
    scene.view_settings.look = "None"
    bpy.context.view_layer.use_pass_z = True
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "ZIP"
    r.filepath = args.output


def render(scene, args):
    """Each frame (one for a still) to the output's name for it, and to --png's."""
    exr = scene.render.image_settings
    for frame in range(1, args.frames + 1):
        scene.frame_set(frame)
        scene.render.filepath = frame_name(args.output, frame)
        bpy.ops.render.render(write_still=True)
        if args.png:
            image = bpy.data.images["Render Result"]
            kept = (exr.file_format, exr.color_mode, exr.color_depth)
            exr.file_format, exr.color_mode, exr.color_depth = "PNG", "RGB", "8"
            image.save_render(frame_name(args.png, frame), scene=scene)
            exr.file_format, exr.color_mode, exr.color_depth = kept


def main():
    args = arguments()
    scene = bpy.context.scene
    build_set()
    place_camera(scene, args)
    configure(scene, args)
    if args.blend:
        bpy.ops.wm.save_as_mainfile(filepath=args.blend)
    render(scene, args)


main()
