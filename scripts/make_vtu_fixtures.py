#!/usr/bin/python3
"""Write the VTK XML (.vtu/.vtp) test fixtures in tests/data/vtu/.

Source: tests/data/splishsplash/vtk/ParticleData_Fluid_21.vtk, a legacy binary
VTK file written by SPlisHSPlasH (MIT licence), 6859 particles with the point
arrays id (UInt32), density (Float32) and velocity (Float32 x3).

VTK itself (python3-vtk9) reads that file with vtkUnstructuredGridReader and
writes it back with vtkXMLUnstructuredGridWriter / vtkXMLPolyDataWriter in every
data layout the XML writers offer, so the fixtures are genuine VTK output.
The float32 values pass through unchanged, so each fixture holds the same bits
as the legacy file (the ascii one: the first ASCII_POINTS particles only, to
keep it small).

Run from anywhere:  /usr/bin/python3 scripts/make_vtu_fixtures.py
"""
import os
import sys

import vtk

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCE = os.path.join(REPO, "tests", "data", "splishsplash", "vtk", "ParticleData_Fluid_21.vtk")
OUT = os.path.join(REPO, "tests", "data", "vtu")
ASCII_POINTS = 500


def read_legacy():
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(SOURCE)
    r.ReadAllScalarsOn()
    r.ReadAllVectorsOn()
    r.ReadAllFieldsOn()
    r.Update()
    grid = r.GetOutput()
    if grid.GetNumberOfPoints() != 6859:
        sys.exit("unexpected point count %d in %s" % (grid.GetNumberOfPoints(), SOURCE))
    names = [grid.GetPointData().GetArrayName(i) for i in range(grid.GetPointData().GetNumberOfArrays())]
    if sorted(names) != ["density", "id", "velocity"]:
        sys.exit("unexpected point arrays %s" % names)
    return grid


def first_points(grid, n):
    """A new grid holding the first n particles (one VTK_VERTEX each)."""
    pts = vtk.vtkPoints()
    pts.SetDataTypeToFloat()
    src = grid.GetPoints()
    for i in range(n):
        pts.InsertNextPoint(src.GetPoint(i))  # float32 -> double -> float32 is exact
    sub = vtk.vtkUnstructuredGrid()
    sub.SetPoints(pts)
    sub.Allocate(n)
    for i in range(n):
        sub.InsertNextCell(vtk.VTK_VERTEX, 1, [i])
    pd = grid.GetPointData()
    for k in range(pd.GetNumberOfArrays()):
        a = pd.GetArray(k)
        b = a.NewInstance()
        b.SetName(a.GetName())
        b.SetNumberOfComponents(a.GetNumberOfComponents())
        b.SetNumberOfTuples(n)
        for i in range(n):
            b.SetTuple(i, i, a)
        sub.GetPointData().AddArray(b)
    return sub


def as_polydata(grid):
    poly = vtk.vtkPolyData()
    poly.SetPoints(grid.GetPoints())
    verts = vtk.vtkCellArray()
    for i in range(grid.GetNumberOfPoints()):
        verts.InsertNextCell(1)
        verts.InsertCellPoint(i)
    poly.SetVerts(verts)
    poly.GetPointData().ShallowCopy(grid.GetPointData())
    return poly


def write(writer_cls, data, name, mode, encode=False, compress=False, header64=False,
          big_endian=False, block_size=None, id32=True, compressor="zlib"):
    """compress: with `compressor`, "zlib", "lz4" or "lzma" (VTK's three)."""
    w = writer_cls()
    w.SetInputData(data)
    w.SetFileName(os.path.join(OUT, name))
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary,
     "appended": w.SetDataModeToAppended}[mode]()
    w.SetEncodeAppendedData(1 if encode else 0)
    if compress:
        {"zlib": w.SetCompressorTypeToZLib, "lz4": w.SetCompressorTypeToLZ4,
         "lzma": w.SetCompressorTypeToLZMA}[compressor]()
    else:
        w.SetCompressorTypeToNone()
    if block_size:
        w.SetBlockSize(block_size)
    if header64:
        w.SetHeaderTypeToUInt64()
    else:
        w.SetHeaderTypeToUInt32()
    if big_endian:
        w.SetByteOrderToBigEndian()
    else:
        w.SetByteOrderToLittleEndian()
    if id32:
        w.SetIdTypeToInt32()  # cell connectivity as Int32: smaller files
    if not w.Write():
        sys.exit("writing %s failed" % name)
    print("%-42s %8d bytes" % (name, os.path.getsize(os.path.join(OUT, name))))


def main():
    os.makedirs(OUT, exist_ok=True)
    grid = read_legacy()
    ug = vtk.vtkXMLUnstructuredGridWriter
    write(ug, first_points(grid, ASCII_POINTS), "fluid21_ascii_first500.vtu", "ascii")
    write(ug, grid, "fluid21_binary.vtu", "binary")
    write(ug, grid, "fluid21_binary_zlib.vtu", "binary", compress=True)
    write(ug, grid, "fluid21_appended_raw.vtu", "appended")
    write(ug, grid, "fluid21_appended_raw_zlib.vtu", "appended", compress=True, block_size=8192)
    write(ug, grid, "fluid21_appended_base64.vtu", "appended", encode=True)
    write(ug, grid, "fluid21_appended_base64_zlib.vtu", "appended", encode=True, compress=True)
    write(ug, grid, "fluid21_uint64_binary_zlib.vtu", "binary", compress=True, header64=True)
    write(ug, grid, "fluid21_uint64_appended_raw_zlib.vtu", "appended", compress=True,
          header64=True, id32=False)
    write(ug, grid, "fluid21_bigendian_binary.vtu", "binary", big_endian=True)
    write(ug, grid, "fluid21_bigendian_appended_raw_zlib.vtu", "appended", compress=True,
          big_endian=True)
    write(vtk.vtkXMLPolyDataWriter, as_polydata(grid), "fluid21_polydata.vtp", "appended",
          compress=True)
    total = sum(os.path.getsize(os.path.join(OUT, f)) for f in os.listdir(OUT))
    print("total %d bytes in %s" % (total, OUT))


if __name__ == "__main__":
    main()
