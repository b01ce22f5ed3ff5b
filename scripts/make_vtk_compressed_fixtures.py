#!/usr/bin/python3
"""Write the LZ4/LZMA-compressed VTK XML fixtures in tests/data/vtk_compressed/.

VTK itself (python3-vtk9, VTK 9.1) reads the SPlisHSPlasH frame of
tests/data/vtu (scripts/make_vtu_fixtures.py: read_legacy, first_points) and
writes its first POINTS particles with vtkXMLUnstructuredGridWriter and
vtkXMLPolyDataWriter, SetCompressorTypeToLZ4 / SetCompressorTypeToLZMA, in
several layouts. tests/io_vtu_test.cpp checks each against the same particles
of tests/data/vtu/fluid21_binary.vtu.

Run from anywhere:  /usr/bin/python3 scripts/make_vtk_compressed_fixtures.py
"""
import importlib.util
import os

import vtk

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
POINTS = 500


def main():
    spec = importlib.util.spec_from_file_location(
        "make_vtu_fixtures", os.path.join(REPO, "scripts", "make_vtu_fixtures.py"))
    fx = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fx)
    fx.OUT = os.path.join(REPO, "tests", "data", "vtk_compressed")
    os.makedirs(fx.OUT, exist_ok=True)
    grid = fx.first_points(fx.read_legacy(), POINTS)
    ug = vtk.vtkXMLUnstructuredGridWriter
    for c in ("lz4", "lzma"):
        base = "fluid21_first500_" + c
        fx.write(ug, grid, base + "_appended_raw.vtu", "appended", compress=True, block_size=4096, compressor=c)
        fx.write(ug, grid, base + "_binary.vtu", "binary", compress=True, compressor=c)
        fx.write(ug, grid, base + "_appended_base64_uint64.vtu", "appended", encode=True, compress=True,
                 header64=True, compressor=c)
        fx.write(vtk.vtkXMLPolyDataWriter, fx.as_polydata(grid), base + "_polydata.vtp", "appended",
                 compress=True, compressor=c)


if __name__ == "__main__":
    main()
