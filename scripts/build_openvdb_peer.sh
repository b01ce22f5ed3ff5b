#!/usr/bin/env bash
# Builds the isosurface peer (OpenVDB ParticlesToLevelSet + volumeToMesh) from
# ../shared/peers/openvdb_mesh into build/openvdb_mesh, for
#   build/bench --mesh-only --openvdb build/openvdb_mesh
# Needs libopenvdb-dev and libboost-dev (apt-get install -y libopenvdb-dev libboost-dev). Not part of CI.
set -euo pipefail
cd "$(dirname "$0")/.."
src=${OPENVDB_PEER_SRC:-../shared/peers/openvdb_mesh/openvdb_mesh.cpp}
[ -f "$src" ] || { echo "build_openvdb_peer.sh: $src not found (set OPENVDB_PEER_SRC)" >&2; exit 1; }
mkdir -p build
g++ -O3 -std=c++17 "$src" -o build/openvdb_mesh -lopenvdb -ltbb -lImath-3_1 -lpthread
echo "built build/openvdb_mesh"
