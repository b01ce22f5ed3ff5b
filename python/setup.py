"""Builds the meniscus package with the project's own CMake build (pyproject.toml).

pip install --no-build-isolation ./python   (from a checkout; needs the C++ build dependencies,
                                             scripts/install_deps.sh, and python3-setuptools)

Environment: MENISCUS_BUILD_DIR reuses an existing CMake build folder (default: a
folder of setuptools' own); CMAKE_BUILD_PARALLEL_LEVEL sets the build's jobs.
"""
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def version():
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        return re.search(r"project\(meniscus VERSION (\S+)", f.read()).group(1)


class CMakeBuild(build_ext):
    """The extension is the CMake target meniscus_python; its folder holds the whole package."""

    def build_extension(self, ext):
        build = os.environ.get("MENISCUS_BUILD_DIR") or os.path.join(os.path.abspath(self.build_temp), "cmake")
        subprocess.check_call(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                               "-DPython3_EXECUTABLE=" + sys.executable, "-DMENISCUS_PYTHON=ON"])
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.check_call(["cmake", "--build", build, "--target", "meniscus_python", "-j", jobs])
        package = os.path.join(build, "python", "meniscus")
        built = [f for f in os.listdir(package) if f.startswith("_meniscus") and f.endswith(".so")]
        if len(built) != 1:
            raise RuntimeError("expected one _meniscus*.so in %s, found %s" % (package, built))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(os.path.join(package, built[0]), target)


setup(
    version=version(),
    packages=["meniscus"],
    package_data={"meniscus": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("meniscus._meniscus", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
