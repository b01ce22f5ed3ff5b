"""meniscus.render and Renderer: the CLI's PNG byte for byte, AOVs, settings."""
import os
import tempfile
import unittest

import numpy as np

import meniscus
from util import DATA, H, SMALL_FRAME, W, cli_png, png_bytes

SIZE = ["--width", str(W), "--height", str(H)]


class RenderMatchesCliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.frame = meniscus.read(SMALL_FRAME)

    def check(self, cli_args, backend="cpu", alpha=False, **settings):
        expected = cli_png("render", SMALL_FRAME, *SIZE, "--backend", backend, *cli_args)
        image = meniscus.render(self.frame, width=W, height=H, backend=backend, **settings)
        self.assertEqual(image.shape, (H, W, 4))
        self.assertEqual(image.dtype, np.uint8)
        # The CLI's PNG is RGB over the studio, RGBA over no background.
        self.assertTrue(png_bytes(image, alpha) == expected, "render(%s) differs from the CLI's PNG" % settings)
        return image

    def test_defaults(self):
        image = self.check([])
        # Positions alone give the same image: the default look reads no attribute.
        same = meniscus.render(self.frame["position"], width=W, height=H, backend="cpu")
        np.testing.assert_array_equal(same, image)
        # float64 is converted to the same float32.
        same = meniscus.render(self.frame["position"].astype(np.float64), width=W, height=H, backend="cpu")
        np.testing.assert_array_equal(same, image)

    def test_options(self):
        self.check(["--filter", "curvature-flow", "--iterations", "4", "--material", "lava", "--azimuth", "-60",
                    "--elevation", "10", "--noise", "--noise-bump", "0.4", "--whiten", "--fill-holes", "0",
                    "--anisotropy", "off", "--radius", "0.03"],
                   filter="curvature-flow", iterations=4, material="lava", azimuth=-60, elevation=10, noise=True,
                   noise_bump=0.4, whiten=True, fill_holes=0, anisotropy=False, radius=0.03)

    def test_camera_and_view(self):
        self.check(["--eye", "-1.5,1.2,2.5", "--target", "0.4,0.2,0.3", "--fov", "50", "--view", "normals"],
                   camera={"eye": (-1.5, 1.2, 2.5), "target": [0.4, 0.2, 0.3], "fov": 50}, view="normals")

    def test_surface_mesh_and_background(self):
        self.check(["--surface", "mesh", "--background", "none"], alpha=True, surface="mesh", background="none")

    def test_geometry(self):
        # Scene geometry (docs/geometry.md): inline objects and the tank of
        # SPlisHSPlasH's scene file, as --geometry says them.
        ball = '{"sphere": {"center": [-1.2, 0.2, 0.1], "radius": 0.15}, "material": {"color": [0.8, 0.3, 0.1]}}'
        tank = os.path.join(DATA, "..", "..", "splishsplash_scene", "scenes", "DamBreakModel.json")
        self.check(["--geometry", ball, "--geometry", tank, "--cut-away", "off"], geometry=[ball, tank],
                   cut_away=False)
        # Shadows (docs/geometry.md#shadows): auto, on or off, as --shadows says.
        self.check(["--geometry", ball, "--shadows", "off"], geometry=[ball], shadows="off")
        self.check(["--shadows", "on"], shadows="on")
        with self.assertRaises(ValueError) as caught:
            meniscus.render(self.frame, width=W, height=H, backend="cpu", geometry=["no_such_tank.obj"])
        self.assertIn("no_such_tank.obj", str(caught.exception))

    def test_two_fluids(self):
        path = os.path.join(DATA, "..", "two_fluids", "ParticleData_Fluid_21_phase.bgeo")
        frame = meniscus.read(path)
        expected = cli_png("render", path, *SIZE, "--backend", "cpu", "--fluid-attribute", "phase",
                           "--material", "water,lava")
        image = meniscus.render(frame, width=W, height=H, backend="cpu", fluid=frame["phase"],
                                material=("water", "lava"))
        self.assertTrue(png_bytes(image) == expected)
        with self.assertRaises(TypeError):
            meniscus.render(frame, width=W, height=H, fluid_attribute="phase")

    def test_smoothing_length(self):
        # A file with a smoothing length h and no radius: radii h / (2 h_per_spacing), as the CLI reads it.
        p = self.frame["position"]
        h = np.linspace(0.05, 0.07, len(p), dtype=np.float32)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "h.csv")
            np.savetxt(path, np.column_stack([p, h]), fmt="%.9g", delimiter=",", header="x,y,z,h", comments="")
            for cli_args, settings in (([], {}), (["--h-per-spacing", "1.5"], {"h_per_spacing": 1.5})):
                expected = cli_png("render", path, *SIZE, "--backend", "cpu", *cli_args)
                for frame in (meniscus.read(path), {"position": p, "h": h}):
                    image = meniscus.render(frame, width=W, height=H, backend="cpu", **settings)
                    self.assertTrue(png_bytes(image) == expected, settings)

    def test_demo(self):
        expected = cli_png("demo", *SIZE, "--backend", "cpu")
        image = meniscus.render(meniscus.demo(), radius=meniscus.DEMO_RADIUS, width=W, height=H, backend="cpu")
        self.assertTrue(png_bytes(image) == expected)

    def test_gl(self):
        try:
            meniscus.Renderer(8, 8, backend="gl")
        except RuntimeError as e:  # no GL context: the CLI's --backend gl would fail alike
            self.skipTest("no GL 4.3 context (EGL) here: %s" % e)
        self.check([], backend="gl")


class RenderTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.frames = [meniscus.read(os.path.join(DATA, "ParticleData_Fluid_%d.bgeo" % n)) for n in (1, 9)]

    def test_renderer_across_frames(self):
        # With the noise on, frames 0 and 5 (not consecutive: no turbulence carried over).
        r = meniscus.Renderer(W, H, backend="cpu", noise=True)
        self.assertEqual(r.backend, "cpu")
        for index, frame in zip((0, 5), self.frames):
            np.testing.assert_array_equal(r.render(frame, frame=index),
                                          meniscus.render(frame, width=W, height=H, backend="cpu", noise=True))
        r = meniscus.Renderer(W, H, backend="cpu")
        for frame in self.frames:
            np.testing.assert_array_equal(r.render(frame), meniscus.render(frame, width=W, height=H, backend="cpu"))

    def test_threads(self):
        # The GIL is released while a frame renders: frames rendered on threads,
        # through one Renderer (one frame at a time) or several, are the same.
        from concurrent.futures import ThreadPoolExecutor
        p = self.frames[0]["position"]
        expected = meniscus.render(p, width=W, height=H, backend="cpu")
        shared = meniscus.Renderer(W, H, backend="cpu")
        with ThreadPoolExecutor(4) as pool:
            own = [pool.submit(meniscus.render, p, width=W, height=H, backend="cpu") for _ in range(2)]
            one = [pool.submit(shared.render, p) for _ in range(2)]
            for f in own + one:
                np.testing.assert_array_equal(f.result(), expected)

    def test_aovs(self):
        p = self.frames[0]["position"]
        image, aovs = meniscus.render(p, width=W, height=H, backend="cpu", aovs=True)
        np.testing.assert_array_equal(image, meniscus.render(p, width=W, height=H, backend="cpu"))
        self.assertEqual(aovs["color"].shape, (H, W, 4))
        self.assertEqual(aovs["normal"].shape, (H, W, 3))
        for key in ("depth", "raw_depth", "thickness"):
            self.assertEqual(aovs[key].shape, (H, W), key)
        for key, a in aovs.items():
            self.assertEqual(a.dtype, np.float32, key)
        liquid = np.isfinite(aovs["depth"])
        self.assertTrue(liquid.any() and not liquid.all())
        self.assertTrue((aovs["thickness"][liquid] > 0).all())
        self.assertNotIn("noise", aovs)
        _, aovs = meniscus.render(p, width=W, height=H, backend="cpu", aovs=True, noise=True)
        self.assertEqual(aovs["noise"].shape, (H, W))

    def test_background_arrays(self):
        # One frame's picture (its colour and eye depth) as the set another frame
        # is composited into by the same camera (docs/compositing.md).
        first, second = (f["position"] for f in self.frames)
        cam = meniscus.auto_camera(first, width=W, height=H)
        _, aovs = meniscus.render(first, width=W, height=H, backend="cpu", camera=cam, aovs=True)
        set_rgb, set_depth = aovs["color"], aovs["depth"]
        plain = meniscus.render(second, width=W, height=H, backend="cpu", camera=cam)
        over = meniscus.render(second, backend="cpu", camera=cam, background=(set_rgb[:, :, :3], set_depth))
        self.assertEqual(over.shape, (H, W, 4))  # the arrays' size
        self.assertFalse(np.array_equal(over, plain))
        # Renderer.render takes it too; the same picture.
        r = meniscus.Renderer(W, H, backend="cpu")
        np.testing.assert_array_equal(r.render(second, camera=cam, background=(set_rgb[:, :, :3], set_depth)), over)
        # With its alpha, and the depth's kind named: the same picture (alpha 1 over the studio).
        np.testing.assert_array_equal(meniscus.render(second, backend="cpu", camera=cam, background=(set_rgb, set_depth),
                                                      backdrop_depth_kind="linear"), over)
        # Errors: another size, a wrong shape, not a pair; a string is the studio setting.
        with self.assertRaisesRegex(ValueError, "the picture"):
            meniscus.render(second, width=W + 2, height=H, backend="cpu", camera=cam, background=(set_rgb, set_depth))
        with self.assertRaisesRegex(ValueError, "H x W x 3"):
            meniscus.render(second, backend="cpu", camera=cam, background=(set_depth, set_depth))
        with self.assertRaisesRegex(ValueError, "rgb, depth"):
            r.render(second, camera=cam, background=set_rgb)
        np.testing.assert_array_equal(meniscus.render(second, width=W, height=H, backend="cpu", camera=cam,
                                                      background="studio"), plain)

    def test_auto_camera_round_trip(self):
        p = self.frames[0]["position"]
        cam = meniscus.auto_camera(p, width=W, height=H)
        self.assertEqual(sorted(cam), ["eye", "far", "fov", "near", "target"])
        np.testing.assert_array_equal(meniscus.render(p, width=W, height=H, backend="cpu", camera=cam),
                                      meniscus.render(p, width=W, height=H, backend="cpu"))

    def test_up_axis(self):
        p = self.frames[0]["position"]
        z_up = np.ascontiguousarray(np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1))
        np.testing.assert_array_equal(meniscus.render(z_up, width=W, height=H, backend="cpu", up=(0, 0, 1)),
                                      meniscus.render(p, width=W, height=H, backend="cpu"))

    def test_settings_errors(self):
        p = self.frames[0]["position"]
        with self.assertRaises(TypeError) as e:
            meniscus.render(p, width=W, height=H, no_such_setting=1)
        self.assertIn("noise_bump", str(e.exception))  # lists the valid names
        for bad in ({"width": 0}, {"filter": "blur"}, {"noise": 1}, {"fluid_scale": 0.3}, {"material": "wine"},
                    {"camera": {"eye": (1, 2, 3)}}, {"camera": {"lens": 3}}, {"radius": -1.0}, {"backend": "vulkan"}):
            with self.assertRaises(ValueError, msg=str(bad)) as e:
                meniscus.render(p, **{"width": W, "height": H, **bad})
            self.assertNotIn("--", str(e.exception))  # Python names, not CLI options
        s = meniscus.settings()
        self.assertEqual(s["noise_bump"]["option"], "--noise-bump")
        self.assertEqual(s["width"]["unit"], "px")  # from the library's option table, as --help
        self.assertEqual(s["width"]["group"], "Camera")
        self.assertEqual(s["width"]["default"], "1280")
        self.assertNotIn("fluid_attribute", list(s))
        self.assertIn("h_per_spacing", list(s))


if __name__ == "__main__":
    unittest.main()
