"""The package's surface: every public name documented and in the type stubs."""
import ast
import inspect
import os
import unittest

import meniscus

STUB = os.path.join(os.path.dirname(meniscus.__file__), "__init__.pyi")


class ApiTest(unittest.TestCase):
    def test_docstrings(self):
        for name in meniscus.__all__:
            obj = getattr(meniscus, name)
            if callable(obj):
                self.assertTrue(inspect.getdoc(obj), name)
        for cls in (meniscus.Renderer, meniscus.Simulation):
            for name, member in vars(cls).items():
                if not name.startswith("_"):
                    self.assertTrue(inspect.getdoc(member), cls.__name__ + "." + name)

    def test_stubs_cover_the_package(self):
        self.assertTrue(os.path.exists(os.path.join(os.path.dirname(STUB), "py.typed")))
        with open(STUB) as f:
            tree = ast.parse(f.read())
        defined = set()
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                defined.add(node.name)
            elif isinstance(node, ast.AnnAssign):
                defined.add(node.target.id)
        self.assertEqual(set(meniscus.__all__) - defined, set())

    def test_version(self):
        self.assertRegex(meniscus.__version__, r"^\d+\.\d+\.\d+")


if __name__ == "__main__":
    unittest.main()
