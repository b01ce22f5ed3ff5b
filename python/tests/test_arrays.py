"""Bad arrays and arguments: a ValueError naming the problem, never a crash."""
import unittest

import numpy as np

import meniscus


def ball(n=9, spacing=0.02):
    """A ball of particles on a cubic lattice (spacing 2 r)."""
    g = (np.arange(n) - (n - 1) / 2) * spacing
    p = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    return np.ascontiguousarray(p[np.linalg.norm(p, axis=1) <= (n - 1) / 2 * spacing], dtype=np.float32)


class BadArraysTest(unittest.TestCase):
    p = ball()

    def assertRefused(self, positions, words, **kw):
        """render() refuses it; so do mesh() and estimate_radius() when no keyword is involved."""
        calls = [lambda: meniscus.render(positions, width=16, height=16, backend="cpu", **kw)]
        if not kw:
            calls += [lambda: meniscus.mesh(positions), lambda: meniscus.estimate_radius(positions)]
        for call in calls:
            with self.assertRaises(ValueError) as e:
                call()
            self.assertIn(words, str(e.exception))

    def test_shape(self):
        self.assertRefused(self.p[:, :2], "shape (N, 3)")
        self.assertRefused(self.p.reshape(-1), "shape (N, 3)")
        self.assertRefused(self.p.reshape(-1, 3, 1), "shape (N, 3)")
        self.assertRefused(np.float32(1.0), "shape (N, 3)")

    def test_dtype(self):
        self.assertRefused(self.p.astype(np.int32), "float32 or float64")
        self.assertRefused(self.p.astype(np.float16), "float32 or float64")
        self.assertRefused(np.array([["a", "b", "c"]]), "float32 or float64")

    def test_layout(self):
        self.assertRefused(self.p[::2], "C-contiguous")
        self.assertRefused(np.asfortranarray(self.p), "C-contiguous")

    def test_empty(self):
        self.assertRefused(np.zeros((0, 3), np.float32), "no particles")

    def test_not_finite(self):
        q = self.p.copy()
        q[7, 1] = np.nan
        self.assertRefused(q, "positions[7]")
        q[7, 1] = np.inf
        self.assertRefused(q, "positions[7]")
        q[7, 1] = 1e30
        self.assertRefused(q, "positions")

    def test_attributes(self):
        n = len(self.p)
        self.assertRefused(self.p, "velocity", velocity=np.zeros((n - 1, 3)))
        self.assertRefused(self.p, "density", density=np.zeros((n, 2)))
        self.assertRefused(self.p, "id", id=np.zeros(n, np.float32))
        self.assertRefused(self.p, "fluid[0]", fluid=np.full(n, 9))
        self.assertRefused(self.p, "radii[0]", radii=np.full(n, -1.0))

    def test_dict_needs_position(self):
        with self.assertRaises(ValueError):
            meniscus.render({"velocity": np.zeros((3, 3))}, width=16, height=16)

    def test_lists_and_other_dtypes_are_converted(self):
        image = meniscus.render(self.p, width=32, height=32, backend="cpu")
        np.testing.assert_array_equal(meniscus.render(self.p.tolist(), width=32, height=32, backend="cpu"), image)
        np.testing.assert_array_equal(
            meniscus.render(self.p.astype(">f4"), width=32, height=32, backend="cpu"), image)
        n = len(self.p)
        ids = np.arange(n, dtype=np.int32)
        np.testing.assert_array_equal(
            meniscus.render(self.p, width=32, height=32, backend="cpu", id=ids, velocity=np.zeros((n, 3))), image)


if __name__ == "__main__":
    unittest.main()
