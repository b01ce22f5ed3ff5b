#!/usr/bin/env bash
# Builds the isosurface peer (OpenVDB ParticlesToLevelSet + volumeToMesh) from
# its source file into build/openvdb_mesh, for
#   build/bench --mesh-only --openvdb build/openvdb_mesh
# OPENVDB_PEER_SRC (required): the peer's source file, openvdb_mesh.cpp (it is
# not part of this repository); a relative path is taken from the repository root.
# Needs libopenvdb-dev and libboost-dev (apt-get install -y libopenvdb-dev libboost-dev). Not part of CI.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -n "${OPENVDB_PEER_SRC:-}" ] || { echo "build_openvdb_peer.sh: set OPENVDB_PEER_SRC to the OpenVDB peer's source file (openvdb_mesh.cpp)" >&2; exit 1; }
src=$OPENVDB_PEER_SRC
[ -f "$src" ] || { echo "build_openvdb_peer.sh: $src not found (set OPENVDB_PEER_SRC)" >&2; exit 1; }
mkdir -p build
g++ -O3 -std=c++17 "$src" -o build/openvdb_mesh -lopenvdb -ltbb -lImath-3_1 -lpthread
echo "built build/openvdb_mesh"
