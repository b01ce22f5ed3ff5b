"""meniscus.mesh (a closed surface) and meniscus.simulate (frames of a tiny scene)."""
import collections
import json
import os
import tempfile
import unittest

import numpy as np

import meniscus
from test_arrays import ball

TINY_SCENE = {
    "duration": 0.1,
    "fps": 20,
    "params": {"solver": "dfsph", "radius": 0.02},
    "domain": {"min": [0, 0, 0], "max": [0.3, 0.3, 0.3]},
    "fluid": [{"box": {"min": [0.02, 0.1, 0.02], "max": [0.18, 0.26, 0.18]}}],
}


class MeshTest(unittest.TestCase):
    def test_ball_is_closed(self):
        p = ball(n=11, spacing=0.02)
        vertices, faces, normals = meniscus.mesh(p, radius=0.01)
        self.assertEqual(vertices.dtype, np.float32)
        self.assertEqual(vertices.shape[1], 3)
        self.assertEqual(faces.shape[1], 3)
        self.assertEqual(normals.shape, vertices.shape)
        self.assertGreater(len(faces), 100)
        self.assertTrue(np.isfinite(vertices).all())
        self.assertLess(int(faces.max()), len(vertices))
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-4)
        # Closed and 2-manifold: each edge in exactly two faces, once each way.
        edges = collections.Counter()
        for a, b, c in faces.tolist():
            edges.update([(a, b), (b, c), (c, a)])
        for (a, b), k in edges.items():
            self.assertEqual(k, 1)
            self.assertEqual(edges[(b, a)], 1)
        # Normals point outward, away from the ball's centre.
        self.assertGreater(float(np.einsum("ij,ij->i", vertices, normals).min()), 0.0)
        # The same mesh from float64 and without normals; the radius estimated as the CLI does.
        v2, f2 = meniscus.mesh(p.astype(np.float64), radius=0.01, normals=False)
        np.testing.assert_array_equal(f2, faces)
        np.testing.assert_array_equal(v2, vertices)
        r = meniscus.estimate_radius(p)
        self.assertAlmostEqual(r, 0.01, delta=0.001)
        v3, f3, _ = meniscus.mesh(p)
        v4, f4, _ = meniscus.mesh(p, radius=r)
        np.testing.assert_array_equal(f3, f4)

    def test_attributes_and_write_mesh(self):
        p = ball(n=9, spacing=0.02)
        frame = {"position": p, "velocity": np.tile(np.float32([1.0, -2.0, 0.5]), (len(p), 1)),
                 "fluid": np.zeros(len(p), dtype=np.int64), "temperature": p[:, 0] * 10.0}
        vertices, faces, normals, attributes = meniscus.mesh(frame, radius=0.01,
                                                             interpolate=["velocity", "fluid", "temperature"])
        self.assertEqual(sorted(attributes), ["fluid", "temperature", "velocity"])
        self.assertEqual(attributes["velocity"].shape, vertices.shape)
        self.assertEqual(attributes["fluid"].shape, (len(vertices),))
        # A constant comes back exactly; a linear field close to its value at the vertex.
        np.testing.assert_allclose(attributes["velocity"], np.tile([1.0, -2.0, 0.5], (len(vertices), 1)), rtol=1e-6)
        np.testing.assert_array_equal(attributes["fluid"], 0.0)
        self.assertLess(float(np.abs(attributes["temperature"] - vertices[:, 0] * 10.0).max()), 10.0 * 0.04)
        with self.assertRaisesRegex(ValueError, "no 'pressure' array"):
            meniscus.mesh(frame, radius=0.01, interpolate=["pressure"])
        with self.assertRaisesRegex(ValueError, "must be a dict"):
            meniscus.mesh(p, radius=0.01, interpolate=["velocity"])
        with tempfile.TemporaryDirectory() as tmp:
            for name in ("m.vtp", "m.vtk", "m.ply"):
                meniscus.write_mesh(os.path.join(tmp, name), vertices, faces, normals, attributes)
            # The .vtp's points and point data through read() (VTK XML PolyData).
            back = meniscus.read(os.path.join(tmp, "m.vtp"))
            np.testing.assert_array_equal(back["position"], vertices)
            np.testing.assert_array_equal(back["velocity"], attributes["velocity"])
            np.testing.assert_array_equal(back["Normals"], normals)
            with self.assertRaisesRegex(ValueError, "out of range"):
                meniscus.write_mesh(os.path.join(tmp, "bad.ply"), vertices, faces + len(vertices))
            with self.assertRaisesRegex(ValueError, "must end in"):
                meniscus.write_mesh(os.path.join(tmp, "bad.stl"), vertices, faces)
            self.assertEqual(sorted(os.listdir(tmp)), ["m.ply", "m.vtk", "m.vtp"])

    def test_bad_parameters(self):
        with self.assertRaises(ValueError):
            meniscus.mesh(ball(), radius=0.01, field="vdb")
        with self.assertRaises(ValueError):
            meniscus.mesh(ball(), radius=0.01, cube_size=0.0)
        with self.assertRaises(ValueError):
            meniscus.mesh(ball(), radius=-1.0)


class SimulateTest(unittest.TestCase):
    def test_tiny_scene(self):
        sim = meniscus.simulate(TINY_SCENE)
        self.assertEqual(len(sim), 3)  # t = 0, 0.05, 0.1
        self.assertAlmostEqual(sim.radius, 0.02)
        frames = list(sim)
        self.assertEqual([f["time"] for f in frames], [0.0, 0.05, 0.1])
        n = len(frames[0]["position"])
        self.assertGreater(n, 20)
        for f in frames:
            self.assertEqual(f["position"].shape, (n, 3))
            self.assertEqual(f["velocity"].shape, (n, 3))
            self.assertEqual(f["id"].dtype, np.int64)
            self.assertEqual(f["density"].shape, (n,))
        # The block falls.
        self.assertLess(frames[-1]["position"][:, 1].mean(), frames[0]["position"][:, 1].mean())
        # Frames render like any other (the studio around the tank).
        image = meniscus.render(frames[-1], width=32, height=32, backend="cpu", studio=sim.domain)
        self.assertEqual(image.shape, (32, 32, 4))

    def test_scene_file_and_overrides(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "tiny.json")
            with open(path, "w") as f:
                json.dump(TINY_SCENE, f)
            sim = meniscus.simulate(path, duration=0.05, fps=40, solver="ballistic")
            frames = list(sim)
            self.assertEqual([f["time"] for f in frames], [0.0, 0.025, 0.05])
            with self.assertRaises(FileNotFoundError):
                meniscus.simulate(os.path.join(d, "missing.json"))
        with self.assertRaises(ValueError):
            meniscus.simulate({"domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "raduis": 1})
        with self.assertRaises(ValueError):
            meniscus.simulate(TINY_SCENE, solver="lbm")
        for bad in ({"duration": -1}, {"fps": 0}, {"radius": -0.01}, {"solver": ""}):
            with self.assertRaises(ValueError, msg=str(bad)) as e:
                meniscus.simulate(TINY_SCENE, **bad)
            self.assertIn(list(bad)[0], str(e.exception))  # names the keyword
            self.assertNotIn("--", str(e.exception))

    def test_settings_of_mesh_and_simulate(self):
        # From `meniscus simulate`'s and `meniscus mesh`'s option tables, as their --help.
        s = meniscus.settings("simulate")
        self.assertEqual(sorted(s), ["duration", "fps", "radius", "solver"])
        self.assertEqual(s["duration"]["option"], "--duration")
        self.assertEqual(s["duration"]["unit"], "s")
        self.assertEqual(s["duration"]["group"], "Simulation")
        self.assertEqual(s["fps"]["default"], "")  # the scene's
        m = meniscus.settings("mesh")
        self.assertEqual(m["radius"]["unit"], "m")
        self.assertEqual(m["cube_size"]["option"], "--cube-size")
        self.assertIn("h_per_spacing", list(m))
        with self.assertRaises(ValueError):
            meniscus.settings("paint")


if __name__ == "__main__":
    unittest.main()
