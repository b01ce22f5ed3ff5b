#!/usr/bin/env python3
"""Writes the DualSPHysics fixtures of this folder byte for byte as DualSPHysics
v5 writes its particle output (see README.txt for the source of each layout).

    python3 tests/data/dualsphysics/make_fixtures.py   # from the repository root

A small z-up tank: 8 fixed boundary particles (the floor), 4 of a moving
piston, 4 of a floating box and 24 fluid particles, ids in DualSPHysics'
order (fixed < moving < floating < fluid; JSph::SaveData derives Type from
the id so)."""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def f32(v):
    """v rounded to float32, as DualSPHysics holds positions for output."""
    return struct.unpack('<f', struct.pack('<f', v))[0]


def particles():
    parts = []  # (pos, idp, vel, rho, type, mk, press)
    idp = 0
    for i in range(8):  # fixed floor, type 0, mk 0
        parts.append(((0.02 * i, 0.0, 0.0), idp, (0.0, 0.0, 0.0), 1000.0 + 0.25 * i, 0, 0)); idp += 1
    for i in range(4):  # moving piston, type 1, mk 10
        parts.append(((0.0, 0.02 * i, 0.02), idp, (0.125, 0.0, 0.0), 1000.5, 1, 10)); idp += 1
    for i in range(4):  # floating box, type 2, mk 50
        parts.append(((0.1 + 0.02 * (i % 2), 0.04, 0.1 + 0.02 * (i // 2)), idp, (0.0, 0.0, -0.0625), 999.75, 2, 50)); idp += 1
    for k in range(24):  # fluid, type 3, mk 1: a 4 x 3 x 2 block
        x, y, z = 0.03 + 0.02 * (k % 4), 0.02 + 0.02 * ((k // 4) % 3), 0.02 + 0.02 * (k // 12)
        vel = (0.5 - 0.0625 * (k % 4), 0.03125 * ((k // 4) % 3), -0.25 * (k // 12))
        parts.append(((x, y, z), idp, vel, 998.0 + 0.5 * k, 3, 1)); idp += 1
    out = []
    for pos, i, vel, rho, typ, mk in parts:
        # Tait's equation as DualSPHysics' pressure: B((rho/rho0)^7 - 1), B = 1.6e5 Pa here.
        press = 1.6e5 * ((rho / 1000.0) ** 7 - 1.0)
        out.append((tuple(f32(c) for c in pos), i, tuple(f32(c) for c in vel), f32(rho), typ, mk, f32(press)))
    return out


def fmt_float(v):
    return '%15.7E' % v  # JDataArrays::GetFmtByType(TypeFloat / TypeFloat3)


def save_csv(path, arrays, sep, head=''):
    """JOutputCsv::SaveCsv: head lines, then NAME[.x/.y/.z] + units + sep per
    column, endl; each row every value + sep, endl."""
    with open(path, 'w', newline='\n') as f:
        for line in head.split('\n') if head else []:
            f.write(line + '\n')
        for name, units, dim, _, _ in arrays:
            if dim == 1:
                f.write(name + units + sep)
            else:
                for c in '.x', '.y', '.z':
                    f.write(name + c + units + sep)
        f.write('\n')
        n = len(arrays[0][3])
        for p in range(n):
            for name, units, dim, values, fmt in arrays:
                v = values[p]
                f.write(sep.join(fmt(c) for c in v) if dim == 3 else fmt(v))
                f.write(sep)
            f.write('\n')


def save_vtk(path, pos, arrays):
    """JSpVtkData::SaveVtk: legacy VTK 3.0, BINARY (big-endian) POLYDATA;
    POINTS float, VERTICES of one point each, then POINT_DATA whose first
    array is SCALARS (+ LOOKUP_TABLE default) and the rest one FIELD FieldData;
    1- and 2-byte types as short, uint/int as int, the rest float; a newline
    after each block."""
    n = len(pos)
    with open(path, 'wb') as f:
        w = lambda s: f.write(s.encode())
        w('# vtk DataFile Version 3.0\nvtk output\nBINARY\nDATASET POLYDATA\n')
        w('POINTS %d float\n' % n)
        f.write(b''.join(struct.pack('>3f', *p) for p in pos)); w('\n')
        w('VERTICES %d %d\n' % (n, 2 * n))
        f.write(b''.join(struct.pack('>2i', 1, p) for p in range(n))); w('\n')
        w('POINT_DATA %d\n' % n)
        for k, (name, tp, dim, values) in enumerate(arrays):
            if k == 0:
                w('SCALARS %s %s%s\n' % (name, tp, ' 3' if dim > 1 else ''))
                w('LOOKUP_TABLE default\n')
            else:
                if k == 1:
                    w('FIELD FieldData %d\n' % (len(arrays) - 1))
                w('%s %d %d %s\n' % (name, dim, n, tp))
            code = {'float': 'f', 'int': 'i', 'short': 'h'}[tp]
            flat = [c for v in values for c in (v if dim > 1 else (v,))]
            f.write(struct.pack('>%d%s' % (len(flat), code), *flat)); w('\n')


def main():
    ps = particles()
    pos = [p[0] for p in ps]
    idp = [p[1] for p in ps]
    vel = [p[2] for p in ps]
    rho = [p[3] for p in ps]
    typ = [p[4] for p in ps]
    mk = [p[5] for p in ps]
    press = [p[6] for p in ps]
    u = lambda v: '%u' % v
    # DualSPHysics' own CSV (JSph::SaveData with -sv:csv, v5.2+ names: Rho):
    # Pos, Idp, Vel, Rho, then Type moved to the fifth place; ';' separators.
    save_csv(os.path.join(HERE, 'PartCsv_0000.csv'), [
        ('Pos', ' [m]', 3, pos, fmt_float),
        ('Idp', '', 1, idp, u),
        ('Vel', ' [m/s]', 3, vel, fmt_float),
        ('Rho', ' [kg/m^3]', 1, rho, fmt_float),
        ('Type', '', 1, typ, u),
    ], ';')
    # PartVTK -savecsv's default variables (idp, vel, rhop, type, press; names
    # before v5.2: Rhop), with -csvsep:1 (commas) and two head lines.
    save_csv(os.path.join(HERE, 'PartAll_comma_0000.csv'), [
        ('Pos', ' [m]', 3, pos, fmt_float),
        ('Idp', '', 1, idp, u),
        ('Vel', ' [m/s]', 3, vel, fmt_float),
        ('Rhop', ' [kg/m^3]', 1, rho, fmt_float),
        ('Type', '', 1, typ, u),
        ('Press', ' [Pa]', 1, press, fmt_float),
    ], ',', head='CaseTank (40 particles)\nTime [s]:  0.000000E+00')
    # The same particles as binary legacy VTK through JSpVtkData::SaveVtk,
    # with the arrays PartVTK -vars:+mk,+press adds (Mk is an unsigned short
    # in DualSPHysics: written as short).
    save_vtk(os.path.join(HERE, 'PartAll_0000.vtk'), pos, [
        ('Idp', 'int', 1, idp),
        ('Vel', 'float', 3, vel),
        ('Rhop', 'float', 1, rho),
        ('Type', 'short', 1, typ),
        ('Mk', 'short', 1, mk),
        ('Press', 'float', 1, press),
    ])


if __name__ == '__main__':
    main()
