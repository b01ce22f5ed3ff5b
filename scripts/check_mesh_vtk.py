#!/usr/bin/python3
"""Opens mesh files with VTK's own readers (what ParaView uses: vtkPLYReader,
vtkOBJReader, vtkXMLPolyDataReader for .vtp, vtkPolyDataReader for .vtk) and
counts, from the triangles VTK read, the edges not shared by exactly two
triangles (numpy; vtkFeatureEdges of VTK 9.1 runs out of memory on meshes of a
million triangles), and lists the point data arrays VTK found (name,
components, range). Needs python3-vtk9 and numpy (not part of CI). Exit 1 when
a file does not load, has no normals, or has such an edge.

    /usr/bin/python3 scripts/check_mesh_vtk.py f21.ply m_0021.obj m_0021.vtp m_0021.vtk
"""
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

bad = 0
for path in sys.argv[1:]:
    ext = path.lower().rsplit(".", 1)[-1]
    reader = {"obj": vtk.vtkOBJReader, "vtp": vtk.vtkXMLPolyDataReader, "vtk": vtk.vtkPolyDataReader}.get(
        ext, vtk.vtkPLYReader)()
    reader.SetFileName(path)
    if ext == "vtk":
        reader.ReadAllScalarsOn()
        reader.ReadAllVectorsOn()
        reader.ReadAllFieldsOn()
    reader.Update()
    mesh = reader.GetOutput()
    polys = mesh.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    tris = vtk_to_numpy(polys.GetConnectivityArray()).reshape(-1, 3)
    assert np.all(np.diff(offsets) == 3), "not all triangles"
    pairs = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, uses = np.unique(pairs, axis=0, return_counts=True)
    normals = mesh.GetPointData().GetNormals()
    open_edges = int(np.count_nonzero(uses != 2))
    print(f"{path}: {mesh.GetNumberOfPoints()} points, {mesh.GetNumberOfCells()} triangles, "
          f"normals {'yes' if normals else 'no'}, open or non-manifold edges {open_edges}")
    data = mesh.GetPointData()
    for k in range(data.GetNumberOfArrays()):
        a = data.GetArray(k)
        ranges = [a.GetRange(c) for c in range(a.GetNumberOfComponents())]
        print(f"  point data {a.GetName()}: {a.GetNumberOfComponents()} components, "
              + ", ".join(f"[{lo:.4g}, {hi:.4g}]" for lo, hi in ranges))
    if mesh.GetNumberOfCells() == 0 or not normals or open_edges:
        bad += 1
sys.exit(1 if bad else 0)
