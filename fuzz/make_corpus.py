#!/usr/bin/python3
"""Write the fuzz seed corpus, fuzz/corpus/<reader>/, from the real test data.

Each seed is a real file cut down to its first N particles (a few KB), so that
libFuzzer starts from every layout the readers know, with real values:
  bgeo, bgeo_gz  tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo (partio,
                 SPlisHSPlasH): inflated, the header's point count set to N, the
                 first N point records and the file's own trailer kept; plain and
                 gzip (and two concatenated gzip members).
  vtk            tests/data/splishsplash/vtk/ParticleData_Fluid_21.vtk (SPlisHSPlasH,
                 binary): every section cut to N; plus VTK 9's own legacy writer,
                 ascii and binary.
  vtu, vtp       VTK 9 (python3-vtk9) writing the first N particles in each layout
                 of tests/data/vtu (scripts/make_vtu_fixtures.py does the same for
                 the full frame), and with VTK's LZ4 and LZMA compressors
                 (tests/data/vtk_compressed).
  pvd            ParaView collections (.pvd): hand-made, in the forms ParaView and
                 simulation codes write (parts, groups, no timesteps, out of order).
  ply            the same N particles: VTK's PLY writer (vertex + face elements),
                 and x y z vx vy vz density id in ascii and both binary byte orders.
  csv, xyz       the same N particles as text: plain, ParaView-style, ';' and tab;
                 and DualSPHysics' CSV (tests/data/dualsphysics, also its VTK for vtk).
  mesh_obj, mesh_ply  small meshes (mesh_reader.cpp): what writeMesh writes, and
                 hand-made files in the forms other tools write.
  texture        not written here: tests/data/geometry/checker.png (make_geometry.py)
                 and two 8 x 8 gradient JPEGs, baseline and progressive, written once
                 by libjpeg 6.2 (quality 90).
Deterministic: running it again gives the same files.

Run from anywhere:  /usr/bin/python3 fuzz/make_corpus.py
"""
import gzip
import importlib.util
import os
import struct

import vtk

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(REPO, "tests", "data", "splishsplash")
OUT = os.path.join(REPO, "fuzz", "corpus")
N = 16


def put(reader, name, data):
    os.makedirs(os.path.join(OUT, reader), exist_ok=True)
    with open(os.path.join(OUT, reader, name), "wb") as f:
        f.write(data)


def gz(data):
    return gzip.compress(data, compresslevel=9, mtime=0)


# ---------------------------------------------------------------- BGEO (partio)

def cut_bgeo():
    d = gzip.decompress(open(os.path.join(DATA, "partio", "ParticleData_Fluid_21.bgeo"), "rb").read())
    counts = list(struct.unpack(">9i", d[5:41]))  # version, nPoints, ..., nAttrib
    n_points, n_attr = counts[1], counts[5]
    p, words = 41, 4
    for _ in range(n_attr):
        (name_len,) = struct.unpack(">H", d[p:p + 2])
        p += 2 + name_len
        size, typ = struct.unpack(">Hi", d[p:p + 6])
        p += 6
        words += size
        if typ in (0, 1, 5):
            p += 4 * size
        else:
            raise SystemExit("unexpected attribute type %d" % typ)
    record = 4 * words
    tail = d[p + n_points * record:]
    counts[1] = N
    cut = d[:5] + struct.pack(">9i", *counts) + d[41:p] + d[p:p + N * record] + tail
    put("bgeo", "fluid21_first16.bgeo", cut)
    put("bgeo", "fluid21_first16.bgeo.gz", gz(cut))
    put("bgeo_gz", "fluid21_first16.bgeo.gz", gz(cut))
    half = len(cut) // 2
    put("bgeo_gz", "fluid21_first16_two_members.bgeo.gz", gz(cut[:half]) + gz(cut[half:]))


# ---------------------------------------------------------------- legacy VTK

def cut_vtk():
    d = open(os.path.join(DATA, "vtk", "ParticleData_Fluid_21.vtk"), "rb").read()
    lines = d.split(b"\n", 4)
    head = b"\n".join(lines[:4]) + b"\n"          # version, title, BINARY, DATASET
    n = int(lines[4].split(b"\n", 1)[0].split()[1])  # POINTS n float

    pos = len(head)
    def section(keyword, item_bytes):
        """The first N items of the section at pos; pos moves past the whole section."""
        nonlocal pos
        if not d.startswith(keyword, pos):
            raise SystemExit("expected %r at %d" % (keyword, pos))
        eol = d.index(b"\n", pos) + 1
        pos = eol + item_bytes * n + 1  # the items and their newline
        return d[eol:eol + item_bytes * N]
    out = head
    out += b"POINTS %d float\n" % N + section(b"POINTS", 12) + b"\n"
    out += b"CELLS %d %d\n" % (N, 2 * N) + section(b"CELLS", 8) + b"\n"
    out += b"CELL_TYPES %d\n" % N + section(b"CELL_TYPES", 4) + b"\n"
    if not d.startswith(b"POINT_DATA", pos):
        raise SystemExit("expected POINT_DATA at %d" % pos)
    pos = d.index(b"\n", pos) + 1
    out += b"POINT_DATA %d\n" % N
    scalars = d[pos:d.index(b"\n", d.index(b"\n", pos) + 1) + 1]  # SCALARS + LOOKUP_TABLE lines
    pos += len(scalars)
    out += scalars + d[pos:pos + 4 * N] + b"\n"
    pos += 4 * n + 1
    out += d[pos:d.index(b"\n", pos) + 1]                 # FIELD FieldData 2
    pos = d.index(b"\n", pos) + 1
    for _ in range(2):
        name, comps, _count, typ = d[pos:d.index(b"\n", pos)].split()
        pos = d.index(b"\n", pos) + 1
        size = 4 * int(comps)
        out += b"%s %s %d %s\n" % (name, comps, N, typ) + d[pos:pos + size * N] + b"\n"
        pos += size * n + 1
    if pos != len(d):
        raise SystemExit("unexpected data after the FIELD arrays in the legacy VTK file")
    put("vtk", "fluid21_first16_splishsplash.vtk", out)


# ---------------------------------------------------------------- VTK 9 writers

def load_fixture_script():
    spec = importlib.util.spec_from_file_location(
        "make_vtu_fixtures", os.path.join(REPO, "scripts", "make_vtu_fixtures.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def vtk_writers(fx):
    grid = fx.first_points(fx.read_legacy(), N)
    for binary in (False, True):
        legacy_writer(vtk.vtkUnstructuredGridWriter, grid, "vtk", "vtk9_first16_%s.vtk", binary)

    ug, pd = vtk.vtkXMLUnstructuredGridWriter, vtk.vtkXMLPolyDataWriter
    fx.OUT = os.path.join(OUT, "vtu")
    os.makedirs(fx.OUT, exist_ok=True)
    for name, kw in (("ascii.vtu", dict(mode="ascii")),
                     ("binary.vtu", dict(mode="binary")),
                     ("binary_zlib.vtu", dict(mode="binary", compress=True)),
                     ("appended_raw.vtu", dict(mode="appended")),
                     ("appended_raw_zlib_blocks.vtu", dict(mode="appended", compress=True, block_size=64)),
                     ("appended_base64.vtu", dict(mode="appended", encode=True)),
                     ("appended_base64_zlib.vtu", dict(mode="appended", encode=True, compress=True)),
                     ("uint64_binary_zlib.vtu", dict(mode="binary", compress=True, header64=True)),
                     ("uint64_appended_raw_zlib.vtu", dict(mode="appended", compress=True, header64=True,
                                                           id32=False)),
                     ("bigendian_binary.vtu", dict(mode="binary", big_endian=True)),
                     ("bigendian_appended_raw_zlib.vtu", dict(mode="appended", compress=True,
                                                              big_endian=True)),
                     ("appended_raw_lz4_blocks.vtu", dict(mode="appended", compress=True, block_size=64,
                                                          compressor="lz4")),
                     ("binary_lz4.vtu", dict(mode="binary", compress=True, compressor="lz4")),
                     ("appended_raw_lzma_blocks.vtu", dict(mode="appended", compress=True, block_size=64,
                                                           compressor="lzma")),
                     ("uint64_binary_lzma.vtu", dict(mode="binary", compress=True, header64=True,
                                                     compressor="lzma"))):
        fx.write(ug, grid, "fluid21_first16_" + name, **kw)
    poly = fx.as_polydata(grid)
    fx.OUT = os.path.join(OUT, "vtp")
    os.makedirs(fx.OUT, exist_ok=True)
    for name, kw in (("ascii.vtp", dict(mode="ascii")),
                     ("binary.vtp", dict(mode="binary")),
                     ("appended_raw_zlib.vtp", dict(mode="appended", compress=True))):
        fx.write(pd, poly, "fluid21_first16_" + name, **kw)

    for binary in (False, True):
        legacy_writer(vtk.vtkPLYWriter, poly, "ply", "vtk9_first16_%s.ply", binary)
    return grid


def legacy_writer(writer_cls, data, reader, pattern, binary):
    """A VTK writer with an ASCII/binary file type (legacy VTK, PLY) into corpus/<reader>/."""
    w = writer_cls()
    w.SetInputData(data)
    w.SetFileName(os.path.join(OUT, reader, pattern % ("binary" if binary else "ascii")))
    w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
    os.makedirs(os.path.dirname(w.GetFileName()), exist_ok=True)
    if not w.Write():
        raise SystemExit("writing %s failed" % w.GetFileName())


# ---------------------------------------------------------------- PLY, CSV, XYZ

def rows(grid):
    pd = grid.GetPointData()
    out = []
    for i in range(N):
        x, y, z = grid.GetPoint(i)
        vx, vy, vz = pd.GetArray("velocity").GetTuple3(i)
        out.append((x, y, z, vx, vy, vz, pd.GetArray("density").GetValue(i), int(pd.GetArray("id").GetValue(i))))
    return out


def text_and_ply(grid):
    r = rows(grid)
    props = "".join("property float %s\n" % p for p in ("x", "y", "z", "vx", "vy", "vz", "density"))
    for fmt, order in (("ascii", None), ("binary_little_endian", "<"), ("binary_big_endian", ">")):
        head = ("ply\nformat %s 1.0\ncomment first %d particles of SPlisHSPlasH frame 21\n"
                "element vertex %d\n%sproperty uint id\nend_header\n" % (fmt, N, N, props)).encode()
        if order is None:
            body = "".join("%.9g %.9g %.9g %.9g %.9g %.9g %.9g %d\n" % row for row in r).encode()
        else:
            body = b"".join(struct.pack(order + "7fI", *row) for row in r)
        put("ply", "fluid21_first16_%s.ply" % fmt, head + body)

    num = lambda row: ["%.9g" % v for v in row[:7]] + [str(row[7])]
    for name, header, sep in (("plain.csv", "x,y,z,vx,vy,vz,density,id", ","),
                              ("paraview.csv", '"Points:0","Points:1","Points:2","Velocity:0","Velocity:1",'
                                               '"Velocity:2","density","id"', ","),
                              ("semicolon.csv", "x;y;z;vx;vy;vz;rho;id", ";"),
                              ("tab.csv", "pos_x\tpos_y\tpos_z\tvel_x\tvel_y\tvel_z\tdensity\tid", "\t")):
        put("csv", "fluid21_first16_" + name,
            (header + "\n" + "".join(sep.join(num(row)) + "\n" for row in r)).encode())
    put("xyz", "fluid21_first16.xyz",
        ("# first %d particles of SPlisHSPlasH frame 21\n" % N +
         "".join("%.9g %.9g %.9g\n" % row[:3] for row in r)).encode())
    put("xyz", "fluid21_first16_commas_extra_columns.xyz",
        "".join("%.9g,%.9g,%.9g,%.9g\n\n" % (row[0], row[1], row[2], row[6]) for row in r).encode())


# ---------------------------------------------------------------- meshes (OBJ, PLY)

def mesh_seeds():
    # A tetrahedron as writeMesh writes it (v, vn, f v//n; binary PLY with
    # normals), and by hand: every OBJ corner form, quads and negative
    # indices; ascii PLY with colours, quads and another element; big-endian
    # PLY with the faces first.
    v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    f = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    n = [(-0.57735, -0.57735, -0.57735), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    put("mesh_obj", "tetra_writemesh.obj", (
        "# written by meniscus (isosurface path): 4 vertices, 4 triangles\n" +
        "".join("v %.9g %.9g %.9g\n" % p for p in v) + "".join("vn %.6g %.6g %.6g\n" % q for q in n) +
        "".join("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in f)).encode())
    put("mesh_obj", "cube_corner_forms.obj", (
        "o Cube\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0 1.0\r\nv 0 0 1\r\nv 1 0 1\r\nv 1 1 1\r\nv 0 1 1\r\n"
        "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\nvn 0 0 -1\r\nvn 0 0 1\r\ng sides\r\nusemtl grey\r\n"
        "f 1 4 3 2\r\nf 5/1 6/2 7/3 8/4\r\nf 1//1 2//1 6//1 5//1\r\nf 2/1/1 3/2/1 7/3/1 6/4/1\r\n"
        "f 3 4 8 7 # comment\r\nf -8/-4/-2 -4/-3/-1 -1 -5\r\n").encode())
    head = ("ply\nformat binary_little_endian 1.0\ncomment written by meniscus (isosurface path)\n"
            "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\nelement face 4\n"
            "property list uchar uint vertex_indices\nend_header\n").encode()
    body = b"".join(struct.pack("<6f", *(p + q)) for p, q in zip(v, n))
    body += b"".join(struct.pack("<B3I", 3, *t) for t in f)
    put("mesh_ply", "tetra_writemesh.ply", head + body)
    put("mesh_ply", "quad_ascii_colours.ply", (
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 2\nproperty list uchar int vertex_index\nproperty uchar flags\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 9 9 9\n4 0 1 2 3 7\n3 0 2 3 1\n0 1\n").encode())
    head = ("ply\nformat binary_big_endian 1.0\nelement face 4\nproperty list uint uint vertex_indices\n"
            "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nend_header\n").encode()
    body = b"".join(struct.pack(">4I", 3, *t) for t in f) + b"".join(struct.pack(">3d", *p) for p in v)
    put("mesh_ply", "tetra_faces_first_big_endian.ply", head + body)


def pvd_seeds():
    head = '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n<Collection>\n'
    tail = '</Collection>\n</VTKFile>\n'
    def pvd(rows):
        return (head + "".join("  <DataSet %s/>\n" % r for r in rows) + tail).encode()
    put("pvd", "paraview_series.pvd", pvd(['timestep="%g" group="" part="0" file="f_%04d.vtu"' % (0.05 * i, i)
                                          for i in range(4)]))
    put("pvd", "out_of_order.pvd", pvd(['timestep="0.2" part="0" file="b/f_2.vtu"',
                                        'timestep="0" part="0" file="b/f_0.vtu"',
                                        'timestep="0.1" part="0" file="b/f_1.vtu"']))
    put("pvd", "parts.pvd", pvd(['timestep="%d" part="%d" file="p%d_%d.vtp"' % (t, p, p, t)
                                 for t in range(2) for p in (1, 0)]))
    put("pvd", "no_timesteps.pvd", pvd(['file="a.vtu"', 'file="/abs/b.vtu"']))
    put("pvd", "exponent_times.pvd", pvd(['timestep="1e-3" file="x_1.vtu"', 'timestep=" 2.5E-3 " file="x_2.vtu"']))


# ---------------------------------------------------------------- DualSPHysics

def dualsphysics_seeds():
    # tests/data/dualsphysics (its README.txt: the layouts of DualSPHysics'
    # JOutputCsv and JSpVtkData): ';' CSV with units and a trailing separator,
    # ',' CSV with head lines, binary legacy VTK with Vel/Rhop/Idp/Type.
    src = os.path.join(REPO, "tests", "data", "dualsphysics")
    for reader, name in (("csv", "PartCsv_0000.csv"), ("csv", "PartAll_comma_0000.csv"), ("vtk", "PartAll_0000.vtk")):
        put(reader, "dualsphysics_" + name, open(os.path.join(src, name), "rb").read())


def hdr_seeds():
    """Radiance .hdr environment maps (src/io/radiance_hdr.cpp): flat, adaptive
    run-length and old-style repeat scanlines, an EXPOSURE line, #?RGBE."""
    def header(w, h, extra=b""):
        return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n" + extra + b"\n-Y %d +X %d\n" % (h, w)

    def rle_row(row):
        out = bytes([2, 2, len(row) >> 8, len(row) & 0xFF])
        for c in range(4):
            vals = [p[c] for p in row]
            x = 0
            while x < len(vals):
                run = 1
                while x + run < len(vals) and run < 127 and vals[x + run] == vals[x]:
                    run += 1
                if run >= 3:
                    out += bytes([128 + run, vals[x]])
                    x += run
                else:
                    n = min(run, 128)
                    out += bytes([n]) + bytes(vals[x:x + n])
                    x += n
        return out

    rows = [[(min(255, 16 * x + y), 200 if x < 6 else 40, 7 * y, 128 + (x // 4)) for x in range(12)] for y in range(4)]
    put("environment_hdr", "flat.hdr", header(3, 2) + bytes(range(60, 84)))
    put("environment_hdr", "rle.hdr", header(12, 4) + b"".join(rle_row(r) for r in rows))
    put("environment_hdr", "exposure.hdr", header(12, 4, b"EXPOSURE=2.5\n") + b"".join(rle_row(r) for r in rows))
    put("environment_hdr", "old_rle.hdr", header(300, 1) + bytes([10, 20, 30, 140, 1, 1, 1, 43, 1, 1, 1, 1]))
    put("environment_hdr", "rgbe.hdr", b"#?RGBE\n\n-Y 1 +X 2\n" + bytes([64, 64, 64, 137, 1, 2, 3, 0]))


def main():
    hdr_seeds()
    pvd_seeds()
    dualsphysics_seeds()
    mesh_seeds()
    cut_bgeo()
    cut_vtk()
    grid = vtk_writers(load_fixture_script())
    text_and_ply(grid)
    for reader in sorted(os.listdir(OUT)):
        files = sorted(os.listdir(os.path.join(OUT, reader)))
        size = sum(os.path.getsize(os.path.join(OUT, reader, f)) for f in files)
        print("%-8s %2d files %7d bytes" % (reader, len(files), size))


if __name__ == "__main__":
    main()
