#!/usr/bin/env bash
# Sort-last rendering over MPI: build/bench_mpi on K = 1..4 processes of this
# machine (loopback only), one thread each, then the model of a cluster fitted
# to those lines (scripts/mpi_model.py). Arguments go to bench_mpi (e.g. --width
# 3840 --height 2160 --repeat 9).
# Usage: bash scripts/bench_mpi.sh [bench_mpi options] | tee mpi.txt
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for k in 1 2 3 4; do
  mpirun --oversubscribe --allow-run-as-root -n "$k" build/bench_mpi "$@" | tee -a "$out"
done
python3 scripts/mpi_model.py < "$out"
