"""What the Python tests share: where the data and the CLI are, running the CLI."""
import os
import subprocess
import tempfile
import unittest

SOURCE_DIR = os.environ.get("MENISCUS_SOURCE_DIR",
                            os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
CLI = os.environ.get("MENISCUS_CLI", "")
DATA = os.path.join(SOURCE_DIR, "tests", "data", "splishsplash", "partio")
SMALL_FRAME = os.path.join(DATA, "ParticleData_Fluid_1.bgeo")  # SPlisHSPlasH dam break, r = 0.025 m
# Small images keep the suite fast; the pipeline is the same at any size.
W, H = 160, 96


def cli(*args):
    """Runs the CLI (ctest passes its path in MENISCUS_CLI); returns stdout."""
    if not CLI:
        raise unittest.SkipTest("MENISCUS_CLI is not set (ctest sets it)")
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    if done.returncode != 0:
        raise AssertionError("meniscus %s failed: %s" % (" ".join(args), done.stderr))
    return done.stdout


def cli_png(*args):
    """The bytes of the PNG `meniscus render ... -o X.png` (or demo) writes."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "cli.png")
        cli(*args, "-o", out)
        with open(out, "rb") as f:
            return f.read()


def png_bytes(image, alpha=False):
    """The bytes write_png writes for `image` (the CLI writes RGB over the studio)."""
    import meniscus
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "py.png")
        meniscus.write_png(out, image, alpha=alpha)
        with open(out, "rb") as f:
            return f.read()

