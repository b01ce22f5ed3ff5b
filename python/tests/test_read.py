"""meniscus.read, sequence, demo, estimate_radius, write_png against the CLI."""
import json
import os
import tempfile
import unittest
import warnings

import numpy as np

import meniscus
from util import DATA, SMALL_FRAME, cli


class ReadTest(unittest.TestCase):
    def test_matches_info(self):
        frame = meniscus.read(SMALL_FRAME)
        info = json.loads(cli("info", "--json", SMALL_FRAME))
        p = frame["position"]
        self.assertEqual(p.dtype, np.float32)
        self.assertEqual(p.shape, (info["count"], 3))
        self.assertTrue(p.flags.c_contiguous)
        # The same float32 bounds (the JSON holds them as exact decimals).
        self.assertEqual(p.min(axis=0).tolist(), info["bounds_min"])
        self.assertEqual(p.max(axis=0).tolist(), info["bounds_max"])
        self.assertEqual(meniscus.estimate_radius(frame), np.float32(info["radius_estimate"]))
        for a in info["attributes"]:
            values = frame[a["name"]]
            self.assertEqual(len(values), info["count"], a["name"])
            self.assertEqual(values.dtype, np.int64 if a["type"].startswith("int") else np.float32, a["name"])
            self.assertEqual(values.shape[1:], () if a["components"] == 1 else (a["components"],), a["name"])
        self.assertEqual(frame["velocity"].shape, (info["count"], 3))
        self.assertEqual(frame["id"].dtype, np.int64)

    def test_path_like_and_vtk(self):
        import pathlib
        bgeo = meniscus.read(pathlib.Path(SMALL_FRAME))
        vtk = meniscus.read(os.path.join(DATA, "..", "vtk", "ParticleData_Fluid_1.vtk"))
        np.testing.assert_array_equal(bgeo["position"], vtk["position"])

    def test_sequence(self):
        frames = meniscus.sequence(DATA)
        self.assertEqual([os.path.basename(f) for f in frames],
                         ["ParticleData_Fluid_%d.bgeo" % n for n in (1, 9, 21, 61)])
        self.assertEqual(meniscus.sequence(os.path.join(DATA, "ParticleData_Fluid_*.bgeo")), frames)
        with self.assertRaises(FileNotFoundError):
            meniscus.sequence(os.path.join(DATA, "nothing_*.bgeo"))

    def test_file_errors(self):
        with self.assertRaises(FileNotFoundError) as e:
            meniscus.read(os.path.join(DATA, "missing.bgeo"))
        self.assertIn("missing.bgeo", str(e.exception))
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "bad.bgeo")
            with open(bad, "wb") as f:
                f.write(b"not a bgeo file at all")
            with self.assertRaises(OSError) as e:
                meniscus.read(bad)
            self.assertNotIsInstance(e.exception, FileNotFoundError)
            self.assertIn("bad.bgeo", str(e.exception))
        # A device has no end to read to: said so, not "file is empty".
        if os.path.exists("/dev/zero"):
            with self.assertRaises(OSError) as e:
                meniscus.read("/dev/zero")
            self.assertIn("/dev/zero: is not a regular file", str(e.exception))

    def test_nan_rows_dropped_with_a_warning(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "f.csv")
            with open(path, "w") as f:
                f.write("x,y,z,density\n0,0,0,1000\nnan,1,1,999\n1,1,1,998\n")
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                frame = meniscus.read(path)
            self.assertEqual(frame["position"].tolist(), [[0, 0, 0], [1, 1, 1]])
            self.assertEqual(frame["density"].tolist(), [1000, 998])
            self.assertTrue(any("non-finite" in str(w.message) or "dropped" in str(w.message) for w in caught),
                            [str(w.message) for w in caught])

    def test_demo(self):
        frame = meniscus.demo()
        self.assertGreater(len(frame["position"]), 1000)
        self.assertAlmostEqual(meniscus.DEMO_RADIUS, 0.025, places=6)

    def test_write_png(self):
        img = np.zeros((4, 5, 4), np.uint8)
        img[..., 0] = 255
        img[..., 3] = 128
        with tempfile.TemporaryDirectory() as d:
            for alpha, name in ((None, "rgba.png"), (False, "rgb.png")):
                path = os.path.join(d, name)
                meniscus.write_png(path, img, alpha=alpha)
                with open(path, "rb") as f:
                    head = f.read(26)
                self.assertEqual(head[:8], b"\x89PNG\r\n\x1a\n")
                self.assertEqual(head[25], 6 if alpha is None else 2)  # colour type RGBA / RGB
            with self.assertRaises(ValueError):
                meniscus.write_png(os.path.join(d, "x.png"), img.astype(np.float32))
            with self.assertRaises(ValueError):
                meniscus.write_png(os.path.join(d, "x.png"), img[..., 0])
            with self.assertRaises(OSError):
                meniscus.write_png(os.path.join(d, "no", "such", "dir.png"), img)


if __name__ == "__main__":
    unittest.main()
