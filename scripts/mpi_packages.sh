#!/usr/bin/env bash
# The system packages that fdem's `mpi` feature needs to build and run: Open MPI (its
# development files and `mpirun`) and libclang (the MPI bindings are generated at build
# time). Installs the missing ones from Debian's packages when this runs as root with
# apt-get (CI's fresh Debian/Ubuntu machine); otherwise names them and the command to run,
# and exits with 1. `--check` only tells: exit 0 when all are there, 1 (naming the missing
# ones) when not. Called by .ci/run (clippy with the feature) and tests/mpi/mpi_runs.sh.
set -euo pipefail

need=()
command -v mpirun >/dev/null 2>&1 || need+=(openmpi-bin)
dpkg -s libopenmpi-dev >/dev/null 2>&1 || need+=(libopenmpi-dev)
dpkg -s libclang-dev >/dev/null 2>&1 || need+=(libclang-dev)
((${#need[@]})) || exit 0

if [ "${1:-}" = --check ]; then
  echo "missing ${need[*]}"
  exit 1
fi
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "installing ${need[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
else
  echo "error: the mpi feature needs ${need[*]} (Debian packages)" >&2
  echo "  fix: sudo apt-get install ${need[*]}" >&2
  exit 1
fi
