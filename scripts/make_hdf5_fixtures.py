#!/usr/bin/python3
"""Write the HDF5 and .npz particle fixtures, tests/data/hdf5/, and the fuzz
seeds fuzz/corpus/hdf5/ and fuzz/corpus/npz/ (tests/data/hdf5/README.txt says
what each file is).

Every file is written by the real libraries: h5py (Debian 12 python3-h5py,
HDF5 1.10.8) for .h5part and .hdf5, numpy.savez / savez_compressed (Debian 12
python3-numpy) for .npz, and Python's zipfile for the deliberately broken
archives. The layouts follow the writers' own code:
  H5Part   groups Step#N of 1-D datasets (H5Part / H5hut; Bethel et al. 2005).
  PySPH    pysph/solver/output.py (github.com/pypr/pysph): HDFOutput._dump
           (particles/<array>/arrays/<prop> with attributes stored, name, type,
           default, stride; constants; solver_data attributes; gzip level 9)
           and NumpyOutput._dump (savez(fname, version=2, particles=...,
           solver_data=...), the particle dict as get_particles_info builds
           it, plus 'arrays').
The real frame is tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo
(SPlisHSPlasH, 6 859 particles), read here with a small BGEO reader, its
float32 values copied bit for bit.

Run from anywhere:  /usr/bin/python3 scripts/make_hdf5_fixtures.py
"""
import gzip
import os
import struct
import zipfile

import h5py
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(REPO, "tests", "data", "hdf5")
CORPUS = os.path.join(REPO, "fuzz", "corpus")
BGEO = os.path.join(REPO, "tests", "data", "splishsplash", "partio", "ParticleData_Fluid_21.bgeo")


def path(name):
    os.makedirs(OUT, exist_ok=True)
    return os.path.join(OUT, name)


def new_h5(p):
    # The oldest file format HDF5 1.8+ reads; no object timestamps, so the
    # same input gives the same bytes.
    if os.path.exists(p):
        os.remove(p)
    return h5py.File(p, "w", libver="earliest", track_order=False)


def dataset(group, name, data, **kw):
    return group.create_dataset(name, data=data, track_times=False, **kw)


# ---------------------------------------------------------------- the real frame

def read_bgeo(p):
    """Houdini BGEO V5 as partio writes it (SPlisHSPlasH): positions and the
    point attributes (id int, density float, velocity vector), big-endian."""
    d = open(p, "rb").read()
    if d[:2] == b"\x1f\x8b":
        d = gzip.decompress(d)
    assert d[:5] == b"BgeoV", "not a BGEO V file"
    counts = struct.unpack(">9i", d[5:41])
    n_points, n_attr = counts[1], counts[5]
    p = 41
    attrs = []
    for _ in range(n_attr):
        (name_len,) = struct.unpack(">H", d[p:p + 2])
        name = d[p + 2:p + 2 + name_len].decode()
        p += 2 + name_len
        size, typ = struct.unpack(">Hi", d[p:p + 6])
        p += 6 + 4 * size  # the defaults
        attrs.append((name, size, typ))
    words = 4 + sum(a[1] for a in attrs)
    rec = np.frombuffer(d, dtype=">u4", count=n_points * words, offset=p).reshape(n_points, words)
    pos = rec[:, 0:3].copy().view(">f4").astype("<f4")
    out = {}
    w = 4
    for name, size, typ in attrs:
        col = rec[:, w:w + size].copy()
        w += size
        out[name] = col.view(">i4").astype("<i4") if typ == 1 else col.view(">f4").astype("<f4")
    return pos, out


def real_frame_h5part():
    pos, a = read_bgeo(BGEO)
    with new_h5(path("splishsplash_fluid21.h5part")) as f:
        f.attrs["Creator"] = np.bytes_("meniscus scripts/make_hdf5_fixtures.py (h5py)")
        s = f.create_group("Step#21")
        s.attrs["TimeStep"] = np.int64(21)
        opts = dict(compression="gzip", compression_opts=6, shuffle=True)
        for k, axis in enumerate("xyz"):
            dataset(s, axis, pos[:, k], **opts)
        for k, axis in enumerate(("vx", "vy", "vz")):
            dataset(s, axis, a["velocity"][:, k], **opts)
        dataset(s, "density", a["density"][:, 0], **opts)
        dataset(s, "id", a["id"][:, 0], **opts)
    return pos, a


# ---------------------------------------------------------------- H5Part sequences

def block(n, t, seed):
    """n particles of a small falling block at time t (float64)."""
    rng = np.random.default_rng(seed)
    side = int(round(n ** (1 / 3))) + 1
    g = np.stack(np.meshgrid(*[np.arange(side)] * 3, indexing="ij"), -1).reshape(-1, 3)[:n]
    p = 0.02 * g + 0.002 * rng.standard_normal((n, 3))
    p[:, 1] += 0.5 - 0.5 * 9.81 * t * t
    return p


def steps_h5part(p, steps):
    with new_h5(p) as f:
        for number, n in steps:
            s = f.create_group("Step#%d" % number)
            s.attrs["TimeStep"] = np.int64(number)
            s.attrs["time"] = np.float64(0.01 * number)
            pos = block(n, 0.01 * number, number)
            dataset(s, "x", pos[:, 0])  # float64: read as float
            dataset(s, "y", pos[:, 1])
            dataset(s, "z", pos[:, 2])
            dataset(s, "vx", np.full(n, 0.5, "<f4"))
            dataset(s, "vy", (-9.81 * 0.01 * number * np.ones(n)).astype("<f4"))
            dataset(s, "vz", np.zeros(n, "<f4"))
            dataset(s, "rho", np.linspace(990, 1010, n).astype("<f4"))
            dataset(s, "id", (np.arange(n, dtype="<i8") + 1_000_000_000_000))  # int64 beyond int32
            dataset(s, "h", np.full(n, 0.024, "<f8"))
            dataset(s, "mass", np.full(n, 0.008, "<f4"))
            dataset(s, "flag", np.arange(n, dtype="<i4") % 3)
            # numpy's own float32 rounding of x, y, z: what the reader must give.
            dataset(s, "xf", pos[:, 0].astype("<f4"))
            dataset(s, "yf", pos[:, 1].astype("<f4"))
            dataset(s, "zf", pos[:, 2].astype("<f4"))


def bad_h5part():
    with new_h5(path("bad_no_steps.h5part")) as f:
        g = f.create_group("data")
        dataset(g, "x", np.zeros(4))
        f.create_group("meta")
    with new_h5(path("bad_step_without_x.h5part")) as f:
        s = f.create_group("Step#0")
        dataset(s, "y", np.zeros(4))
        dataset(s, "z", np.zeros(4))
        dataset(s, "id", np.arange(4, dtype="<i4"))
    with new_h5(path("bad_unequal_lengths.h5part")) as f:
        s = f.create_group("Step#0")
        dataset(s, "x", np.zeros(10))
        dataset(s, "y", np.zeros(10))
        dataset(s, "z", np.zeros(9))
    with new_h5(path("bad_types.h5part")) as f:
        # Step#0: a string dataset beside good ones (skipped with a warning);
        # Step#1: x itself is strings (an error).
        s = f.create_group("Step#0")
        for axis in "xyz":
            dataset(s, axis, np.arange(5, dtype="<f4"))
        dataset(s, "label", np.array([b"a", b"b", b"c", b"d", b"e"]))
        s = f.create_group("Step#1")
        dataset(s, "x", np.array([b"1", b"2"]))
        dataset(s, "y", np.zeros(2, "<f4"))
        dataset(s, "z", np.zeros(2, "<f4"))


# ---------------------------------------------------------------- PySPH

WCSPH_PROPS = ["x", "y", "z", "u", "v", "w", "rho", "h", "m", "p", "cs", "au", "av", "aw", "arho",
               "x0", "y0", "z0", "u0", "v0", "w0", "rho0", "gid", "pid", "tag", "gradv"]


def prop_type(name):
    return {"gid": "unsigned int", "pid": "int", "tag": "int"}.get(name, "double")


def pysph_arrays():
    """Two particle arrays as a 2-D PySPH dam break holds them: 'fluid' (its
    output arrays leave out z and w, as 2-D examples do) and 'boundary'."""
    out = {}
    for name, nx, ny, x0, dx in (("fluid", 12, 10, 0.1, 0.02), ("boundary", 30, 2, 0.0, 0.02)):
        n = nx * ny
        gx, gy = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
        x = (x0 + dx * gx.ravel()).astype("f8")
        y = (x0 + dx * gy.ravel()).astype("f8") if name == "fluid" else (-dx * gy.ravel()).astype("f8")
        hdx = 1.3
        data = {
            "x": x, "y": y, "z": np.zeros(n),
            "u": 0.1 * np.sin(np.arange(n)), "v": -0.2 * np.cos(np.arange(n)), "w": np.zeros(n),
            "rho": 1000.0 + np.arange(n) * 0.25, "h": np.full(n, hdx * dx), "m": np.full(n, 1000.0 * dx * dx),
            "p": np.arange(n) * 10.0, "gid": np.arange(n, dtype=np.uint32), "pid": np.zeros(n, np.int32),
            "tag": np.zeros(n, np.int32), "gradv": np.arange(4 * n, dtype="f8") * 0.5,
        }
        output = (["x", "y", "u", "v", "rho", "m", "h", "p", "pid", "gid", "tag", "gradv"] if name == "fluid"
                  else ["x", "y", "z", "rho", "m", "h", "p", "pid", "gid", "tag"])
        props = {}
        for prop in WCSPH_PROPS:
            props[prop] = {"name": prop, "type": prop_type(prop),
                           "default": 4294967295 if prop == "gid" else (1000.0 if prop == "rho" else 0.0),
                           "stride": 4 if prop == "gradv" else 1, "data": None}
        out[name] = dict(properties=props, constants={"c0": np.array([10.0])},
                         output_property_arrays=output,
                         arrays={k: data[k] for k in output})
    return out


SOLVER_DATA = {"dt": np.float64(1.25e-4), "t": 0.0125, "count": 100}


def pysph_hdf5(p, arrays, names=None, only_stored=False, gzip_level=9):
    """HDFOutput._dump (pysph/solver/output.py), compress=False: gzip 9.
    only_stored: leave out the empty datasets of unstored properties (smaller
    files for the tests that do not need them); gzip_level None: stored
    uncompressed (each gzip dataset costs a few KB of chunk index)."""
    with new_h5(p) as f:
        solver = f.create_group("solver_data")
        particles = f.create_group("particles")
        for name, info in arrays.items():
            name = names.get(name, name) if names else name
            g = particles.create_group(name)
            arrays_grp = g.create_group("arrays")
            consts = g.create_group("constants")
            for c, v in info["constants"].items():
                dataset(consts, c, v)
            for prop, attrs in info["properties"].items():
                if only_stored and prop not in info["arrays"] and prop != "z":
                    continue
                if prop in info["arrays"]:
                    gz = dict(compression="gzip", compression_opts=gzip_level) if gzip_level else {}
                    d = dataset(arrays_grp, prop, info["arrays"][prop], **gz)
                    d.attrs["stored"] = True
                else:
                    d = dataset(arrays_grp, prop, np.zeros((0,), "f4"))
                    d.attrs["stored"] = False
                for k, v in attrs.items():
                    d.attrs[k] = "None" if v is None else v
        for k, v in SOLVER_DATA.items():
            solver.attrs[k] = v


def pysph_npz(p, arrays, compressed=False):
    """NumpyOutput._dump: savez(fname, version=2, particles=..., solver_data=...)."""
    particle_data = {name: {k: v for k, v in info.items()} for name, info in arrays.items()}
    (np.savez_compressed if compressed else np.savez)(p, version=2, particles=particle_data,
                                                       solver_data=dict(SOLVER_DATA))


# ---------------------------------------------------------------- plain npz

def plain_npz():
    n = 50
    pos = block(n, 0.0, 7)
    np.savez(path("plain_arrays.npz"),
             x=pos[:, 0], y=pos[:, 1].astype("<f4"), z=pos[:, 2],
             u=np.full(n, 1.5, "<f4"), v=np.zeros(n, "<f4"), w=np.full(n, -0.5, "<f4"),
             rho=np.linspace(900, 1100, n).astype(">f8"),        # big-endian
             id=np.arange(n, dtype="<i8") * 3, h=np.full(n, 0.026, "<f8"),
             count=np.arange(n, dtype="<u4"), wet=np.arange(n) % 2 == 0,
             note=np.array("not per particle"))
    m = 20
    fluid = block(m, 0.1, 8)
    wall = np.stack([np.linspace(-0.1, 0.1, 10), np.zeros(10), np.zeros(10)], 1)
    vel = np.asfortranarray(np.tile([0.0, -1.0, 0.25], (m, 1)))  # Fortran order
    np.savez_compressed(path("plain_bodies_compressed.npz"),
                        **{"fluid/x": fluid[:, 0], "fluid/y": fluid[:, 1], "fluid/z": fluid[:, 2],
                           "fluid/velocity": vel, "fluid/id": np.arange(m, dtype="<i4"),
                           "wall/position": wall.astype("<f4")})
    return pos, fluid, wall


def npy_bytes(descr, shape, data, fortran=False, version=(1, 0)):
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (descr, fortran, shape)
    pad = 64 - (10 + len(header) + 1) % 64
    header = header + " " * pad + "\n"
    if version == (1, 0):
        head = b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header))
    else:
        head = b"\x93NUMPY" + bytes(version) + struct.pack("<I", len(header))
    return head + header.encode() + data


def writestr(z, name, data):
    # A fixed date, so the same input gives the same bytes.
    z.writestr(zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0)), data)


def broken_npz():
    good = np.arange(8, dtype="<f8").tobytes()
    with zipfile.ZipFile(path("bad_npy_header_lies.npz"), "w") as z:
        # x declares 10^12 elements but holds 8: nothing that size may be allocated.
        writestr(z, "x.npy", npy_bytes("<f8", "(1000000000000,)", good))
        writestr(z, "y.npy", npy_bytes("<f8", "(8,)", good))
        writestr(z, "z.npy", npy_bytes("<f8", "(8,)", good))
    with zipfile.ZipFile(path("bad_npy_truncated.npz"), "w") as z:
        writestr(z, "x.npy", npy_bytes("<f8", "(8,)", good[:40]))
        writestr(z, "y.npy", npy_bytes("<f8", "(8,)", good))
        writestr(z, "z.npy", npy_bytes("<f8", "(8,)", good))
    with zipfile.ZipFile(path("bad_npy_dtype.npz"), "w") as z:
        writestr(z, "x.npy", npy_bytes("<c16", "(8,)", good + good))  # complex128
        writestr(z, "y.npy", npy_bytes("<f8", "(8,)", good))
        writestr(z, "z.npy", npy_bytes("<f8", "(8,)", good))
    with zipfile.ZipFile(path("npy_versions.npz"), "w") as z:
        # .npy 2.0 and 3.0 headers, big-endian int32 and float32.
        writestr(z, "x.npy", npy_bytes(">f4", "(4,)", np.arange(4, dtype=">f4").tobytes(), version=(2, 0)))
        writestr(z, "y.npy", npy_bytes("<f4", "(4,)", np.ones(4, "<f4").tobytes(), version=(3, 0)))
        writestr(z, "z.npy", npy_bytes("<f4", "(4,)", np.zeros(4, "<f4").tobytes()))
        writestr(z, "id.npy", npy_bytes(">i4", "(4,)", np.array([7, -8, 9, 2**31 - 1], ">i4").tobytes()))


# ---------------------------------------------------------------- fuzz seeds

def put_seed(reader, name, src=None, data=None):
    d = os.path.join(CORPUS, reader)
    os.makedirs(d, exist_ok=True)
    if data is None:
        data = open(src, "rb").read()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def fuzz_seeds(arrays):
    tmp = os.path.join(OUT, ".seed.tmp")
    steps_h5part(tmp, [(0, 8), (1, 8)])
    put_seed("hdf5", "h5part_two_steps.h5part", tmp)
    small = {k: dict(v) for k, v in arrays.items()}
    for info in small.values():
        info["arrays"] = {k: v[: 4 * 8 if k == "gradv" else 8] for k, v in info["arrays"].items()}
    pysph_hdf5(tmp, small, only_stored=True, gzip_level=None)
    put_seed("hdf5", "pysph_small.hdf5", tmp)
    os.remove(tmp)
    pysph_npz(tmp, small)
    put_seed("npz", "pysph_small.npz", tmp + ".npz")
    os.remove(tmp + ".npz")
    put_seed("npz", "npy_versions.npz", path("npy_versions.npz"))
    pos = block(8, 0.0, 3)
    np.savez(tmp, x=pos[:, 0], y=pos[:, 1], z=pos[:, 2], id=np.arange(8), u=np.ones(8, "f4"))
    put_seed("npz", "plain_small.npz", tmp + ".npz")
    np.savez_compressed(tmp, **{"fluid/x": pos[:, 0], "fluid/y": pos[:, 1], "fluid/z": pos[:, 2]})
    put_seed("npz", "bodies_small_compressed.npz", tmp + ".npz")
    os.remove(tmp + ".npz")
    # fuzz_npz's own form: a selector byte, then one .npy that the target
    # stores in a zip (odd: as particles.npy; 3: as x.npy, y.npy and z.npy).
    with zipfile.ZipFile(os.path.join(CORPUS, "npz", "pysph_small.npz")) as z:
        put_seed("npz", "member_pysph_particles.npy.seed", data=b"\x01" + z.read("particles.npy"))
    with zipfile.ZipFile(path("npy_versions.npz")) as z:
        put_seed("npz", "member_plain_x.npy.seed", data=b"\x03" + z.read("x.npy"))


def main():
    real_frame_h5part()
    steps_h5part(path("steps.h5part"), [(0, 64), (1, 80), (2, 96), (10, 100)])
    bad_h5part()
    arrays = pysph_arrays()
    pysph_hdf5(path("pysph_dam_break_2d_100.hdf5"), arrays)
    pysph_npz(path("pysph_dam_break_2d_100.npz"), arrays)
    pysph_npz(path("pysph_dam_break_2d_100_compressed.npz"), arrays, compressed=True)
    pysph_hdf5(path("pysph_no_fluid.hdf5"), arrays, names={"fluid": "water", "boundary": "solid"},
               only_stored=True, gzip_level=None)
    plain_npz()
    broken_npz()
    fuzz_seeds(arrays)


if __name__ == "__main__":
    main()
