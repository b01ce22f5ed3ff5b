#!/usr/bin/python3
"""Opens particle files with VTK's own readers, the ones ParaView uses
(vtkGenericDataObjectReader for legacy .vtk, vtkXMLUnstructuredGridReader,
vtkXMLPolyDataReader, vtkPLYReader), and prints per file one line

    FILE points=N cells=C P=<hash> NAME:COMPONENTS:<hash> ...

with FNV-1a 64-bit hashes (hex) of the bytes VTK holds: positions as float32,
each point array as float32 or int32, little-endian. tests/io_writers_test.cpp
compares the line with what it wrote. Needs python3-vtk9 and numpy (the test
skips without them). Exit 1 when a file does not load.

    /usr/bin/python3 scripts/check_particles_vtk.py f.vtk f.vtu f.vtp f.ply
"""
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def fnv(data):
    h = 0xcbf29ce484222325
    for b in data:
        h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
    return format(h, "x")


def reader_for(path):
    p = path.lower()
    if p.endswith(".vtk"):
        return vtk.vtkGenericDataObjectReader()
    if p.endswith(".vtu"):
        return vtk.vtkXMLUnstructuredGridReader()
    if p.endswith(".vtp"):
        return vtk.vtkXMLPolyDataReader()
    return vtk.vtkPLYReader()


bad = 0
for path in sys.argv[1:]:
    reader = reader_for(path)
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutputDataObject(0)
    if data is None or (hasattr(reader, "GetErrorCode") and reader.GetErrorCode() != 0):
        print(f"{path}: VTK could not read it")
        bad += 1
        continue
    n = data.GetNumberOfPoints()
    line = f"{path} points={n} cells={data.GetNumberOfCells()}"
    if n > 0:
        line += " P=" + fnv(vtk_to_numpy(data.GetPoints().GetData()).astype("<f4").tobytes())
        pd = data.GetPointData()
        for i in range(pd.GetNumberOfArrays()):
            arr = pd.GetAbstractArray(i)
            values = vtk_to_numpy(arr)
            kind = "<i4" if np.issubdtype(values.dtype, np.integer) else "<f4"
            line += f" {arr.GetName()}:{arr.GetNumberOfComponents()}:{fnv(values.astype(kind).tobytes())}"
    print(line)
sys.exit(1 if bad else 0)
