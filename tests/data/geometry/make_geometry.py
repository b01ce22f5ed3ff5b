import struct, base64, json
def sub(a,b): return tuple(x-y for x,y in zip(a,b))
def cross(a,b): return (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
def dot(a,b): return sum(x*y for x,y in zip(a,b))
V=[(-1,-1,-1),(1,-1,-1),(1,1,-1),(-1,1,-1),(-1,-1,1),(1,-1,1),(1,1,1),(-1,1,1)]
F=[(0,2,1),(0,3,2),(4,5,6),(4,6,7),(0,1,5),(0,5,4),(3,7,6),(3,6,2),(0,4,7),(0,7,3),(1,2,6),(1,6,5)]
for f in F:
    a,b,c=[V[i] for i in f]
    cen=tuple((x+y+z)/3 for x,y,z in zip(a,b,c))
    assert dot(cross(sub(b,a),sub(c,a)),cen)>0, f
with open('cube.obj','w') as o:
    o.write("# A cube of side 2 centred at the origin, 12 outward (counter-clockwise) triangles; no normals, no material.\n")
    for v in V: o.write("v %g %g %g\n"%v)
    for f in F: o.write("f %d %d %d\n"%tuple(i+1 for i in f))
with open('red_cube.obj','w') as o:
    o.write("# The cube of cube.obj as six quads, with a red material (red_cube.mtl).\nmtllib red_cube.mtl\n")
    for v in V: o.write("v %g %g %g\n"%v)
    o.write("usemtl red\n")
    quads=[(0,3,2,1),(4,5,6,7),(0,1,5,4),(3,7,6,2),(0,4,7,3),(1,2,6,5)]
    for q in quads: o.write("f %d %d %d %d\n"%tuple(i+1 for i in q))
with open('red_cube.mtl','w') as o:
    o.write("# Kd is taken as linear RGB.\nnewmtl red\nKd 0.8 0.1 0.05\n")
with open('cube_ascii.ply','w') as o:
    o.write("ply\nformat ascii 1.0\ncomment the cube of cube.obj\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n")
    for v in V: o.write("%g %g %g\n"%v)
    for f in F: o.write("3 %d %d %d\n"%f)
with open('cube_binary.ply','wb') as o:
    o.write(b"ply\nformat binary_little_endian 1.0\ncomment the cube of cube.obj\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n")
    for v in V: o.write(struct.pack('<3f',*v))
    for f in F: o.write(struct.pack('<B3i',3,*f))
T=[(0,0,0),(1,0,0),(0,1,0),(0,0,1)]
TF=[(0,2,1),(0,1,3),(0,3,2),(1,2,3)]
cen=(0.25,0.25,0.25)
def fn(f):
    a,b,c=[T[i] for i in f]
    n=cross(sub(b,a),sub(c,a)); m=tuple((x+y+z)/3 for x,y,z in zip(a,b,c))
    assert dot(n,sub(m,cen))>0
    l=dot(n,n)**0.5
    return tuple(x/l for x in n)
with open('tetra_ascii.stl','w') as o:
    o.write("solid tetra\n")
    for f in TF:
        n=fn(f); o.write(" facet normal %g %g %g\n  outer loop\n"%tuple(n))
        for i in f: o.write("   vertex %g %g %g\n"%T[i])
        o.write("  endloop\n endfacet\n")
    o.write("endsolid tetra\n")
with open('tetra_binary.stl','wb') as o:
    o.write(b"binary STL: a tetrahedron, corners (0,0,0) (1,0,0) (0,1,0) (0,0,1)".ljust(80,b' '))
    o.write(struct.pack('<I',len(TF)))
    for f in TF:
        o.write(struct.pack('<3f',*fn(f)))
        for i in f: o.write(struct.pack('<3f',*T[i]))
        o.write(struct.pack('<H',0))
pos=b''.join(struct.pack('<3f',*v) for v in V)
idx=b''.join(struct.pack('<3H',*f) for f in F)
buf=pos+idx
g={"asset":{"version":"2.0","generator":"meniscus tests (hand-written)"},
 "scene":0,"scenes":[{"nodes":[0]}],
 "nodes":[{"mesh":0,"translation":[0,2,0],"name":"cube"}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
 "materials":[{"name":"teal","pbrMetallicRoughness":{"baseColorFactor":[0.1,0.5,0.4,1.0],"metallicFactor":0.25,"roughnessFactor":0.3}}],
 "buffers":[{"byteLength":len(buf),"uri":"data:application/octet-stream;base64,"+base64.b64encode(buf).decode()}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":len(pos),"target":34962},
                {"buffer":0,"byteOffset":len(pos),"byteLength":len(idx),"target":34963}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]},
              {"bufferView":1,"componentType":5123,"count":36,"type":"SCALAR"}]}
json.dump(g,open('cube.gltf','w'),indent=1)
# Binary: Assimp's text parsers read "nan" as a number, the binary PLY reader keeps the bits.
with open('nan_vertex.ply','wb') as o:
    o.write(b"ply\nformat binary_little_endian 1.0\ncomment a triangle with a non-finite vertex\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")
    o.write(struct.pack('<9f',0,0,0,1,0,0,float('nan'),1,0))
    o.write(struct.pack('<B3i',3,0,1,2))
with open('lines_only.obj','w') as o:
    o.write("# no triangles: a polyline only\nv 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n")
with open('broken.stl','w') as o:
    o.write("solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0\n")
# A textured unit quad: x and z in [0, 1] at y = 0, facing +y, texture
# coordinates u = x, v = 1 - z (so the image's top edge lies at z = 0), and a
# 4 x 4 PNG of four 2 x 2 blocks (sRGB): red top-left, green top-right, blue
# bottom-left, white bottom-right. As OBJ + MTL + PNG beside it, and as glTF
# with the PNG embedded (a data URI).
import zlib
def png(w, h, rows):
    def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    raw = b''.join(b'\x00' + bytes(r) for r in rows)
    return b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)) + \
        chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b'')
R, G, B, W = (255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 255)
rows = [sum([R, R, G, G], ()), sum([R, R, G, G], ()), sum([B, B, W, W], ()), sum([B, B, W, W], ())]
checker = png(4, 4, rows)
with open('checker.png', 'wb') as o: o.write(checker)
QV = [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)]
QT = [(0, 1), (1, 1), (1, 0), (0, 0)]
with open('textured_quad.obj', 'w') as o:
    o.write("# A unit quad at y = 0 facing +y with texture coordinates and a base colour map (textured_quad.mtl, checker.png).\n")
    o.write("mtllib textured_quad.mtl\n")
    for v in QV: o.write("v %g %g %g\n" % v)
    for t in QT: o.write("vt %g %g\n" % t)
    o.write("vn 0 1 0\nusemtl checker\nf 1/1/1 4/4/1 3/3/1 2/2/1\n")
with open('textured_quad.mtl', 'w') as o:
    o.write("# Kd beside a map: the map is the colour.\nnewmtl checker\nKd 0.8 0.8 0.8\nmap_Kd checker.png\n")
pos = b''.join(struct.pack('<3f', *v) for v in QV)
nrm = b''.join(struct.pack('<3f', 0, 1, 0) for v in QV)
uv = b''.join(struct.pack('<2f', t[0], 1 - t[1]) for t in QT)  # glTF's v runs down the image
idx = struct.pack('<6H', 0, 3, 2, 0, 2, 1)
buf = pos + nrm + uv + idx
gl = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
      "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
      "textures": [{"source": 0}],
      "images": [{"uri": "data:image/png;base64," + base64.b64encode(checker).decode()}],
      "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                      {"buffer": 0, "byteOffset": 96, "byteLength": 32}, {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 0, 1]},
                    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                    {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                    {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}]}
with open('textured_quad.gltf', 'w') as o: json.dump(gl, o)
