#!/usr/bin/env python3
"""Writes a DualSPHysics-like particle CSV (its JOutputCsv layout, as
tests/data/dualsphysics/README.txt describes it: Pos, Idp, Vel, Rho, Type,
';', z up) of a fluid frame inside an open tank of one layer of fixed
boundary particles (Type 0) at spacing DP, for the picture of
docs/geometry.md#dualsphysics-boundaries (scripts/make_readme_images.sh).

    scripts/make_dualsphysics_tank.py FLUID.ply OUT.csv

FLUID.ply is `meniscus convert`'s binary PLY of a y-up frame (x, y, z, id,
vx, vy, vz, density), here frame 21 of the dam break in SPlisHSPlasH's
DamBreakModel tank (x in [-2, 2], y from 0, z in [-0.75, 0.75]); the tank's
particles stand half a spacing outside those walls, up to 2.2 m. Each point
(X, Y, Z) is written z up as (X, -Z, Y), which --up 0,0,1 turns back."""
import struct
import sys

DP = 0.02


def read_ply(path):
    with open(path, 'rb') as f:
        props, count = [], 0
        while True:
            line = f.readline().decode().strip()
            if line.startswith('element vertex'):
                count = int(line.split()[2])
            elif line.startswith('property'):
                props.append((line.split()[1], line.split()[2]))
            elif line == 'end_header':
                break
        fmt = '<' + ''.join({'float': 'f', 'int': 'i'}[t] for t, _ in props)
        size = struct.calcsize(fmt)
        names = [n for _, n in props]
        return [dict(zip(names, struct.unpack(fmt, f.read(size)))) for _ in range(count)]


def tank():
    x0, x1, z0, z1, top = -2.0 - DP / 2, 2.0 + DP / 2, -0.75 - DP / 2, 0.75 + DP / 2, 2.2
    nx, nz, ny = round((x1 - x0) / DP), round((z1 - z0) / DP), round((top + DP / 2) / DP)
    for i in range(nx + 1):
        for j in range(ny + 1):
            for k in range(nz + 1):
                if j == 0 or i in (0, nx) or k in (0, nz):
                    yield (x0 + i * DP, -DP / 2 + j * DP, z0 + k * DP)


def main():
    fluid = read_ply(sys.argv[1])
    sep = ';'
    with open(sys.argv[2], 'w', newline='\n') as out:
        out.write(sep.join(['Pos.x [m]', 'Pos.y [m]', 'Pos.z [m]', 'Idp', 'Vel.x [m/s]', 'Vel.y [m/s]',
                            'Vel.z [m/s]', 'Rho [kg/m^3]', 'Type']) + sep + '\n')
        idp = 0

        def row(p, v, rho, typ):
            nonlocal idp
            x, y, z = p
            vx, vy, vz = v
            cells = ['%15.7E' % c for c in (x, -z, y)] + ['%u' % idp] + ['%15.7E' % c for c in (vx, -vz, vy)]
            out.write(sep.join(cells + ['%15.7E' % rho, '%u' % typ]) + sep + '\n')
            idp += 1

        for p in tank():  # fixed boundary first, as DualSPHysics numbers them
            row(p, (0.0, 0.0, 0.0), 1000.0, 0)
        for q in fluid:
            row((q['x'], q['y'], q['z']), (q['vx'], q['vy'], q['vz']), q['density'], 3)


if __name__ == '__main__':
    main()
