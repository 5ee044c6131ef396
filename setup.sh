#!/usr/bin/env bash
# Installs every system package signorini needs on Debian 12 (PETSc 3.18 with MUMPS and hypre,
# libclang for bindgen, Open MPI, Gmsh, an optimised BLAS/LAPACK) and Python meshio for the tests.
# Idempotent and quiet when everything is already there. Uses sudo when not run as root.
set -euo pipefail

# Rust: signorini needs rustc >= 1.87 (rustup); Debian 12's own rustc (1.63) is too old.
if ! command -v cargo >/dev/null 2>&1; then
  echo "setup: no cargo on PATH: install Rust >= 1.87 with rustup (https://rustup.rs), then run this again" >&2
  exit 1
fi
rust_minor=$(rustc --version | sed -E 's/^rustc 1\.([0-9]+).*/\1/')
if [ "${rust_minor:-0}" -lt 87 ]; then
  echo "setup: $(rustc --version) is too old: signorini needs Rust >= 1.87 (rustup update)" >&2
  exit 1
fi

# libopenblas0-serial: PETSc and MUMPS link the BLAS/LAPACK chosen by Debian's alternatives, which
# is the slow reference BLAS unless an optimised one is installed (MUMPS factorisations 3-4x
# faster at 1e6 dofs). Serial, not threaded: parallelism comes from MPI ranks, and threaded BLAS
# under `mpirun -n N` oversubscribes the cores.
# libhdf5-mpi-dev: the HDF5 headers and hdf5.pc for the FCLIB export (crate hdf5-metno), of the
# Open MPI build of HDF5 that PETSc already links, so that one HDF5 library is loaded (the
# serial libhdf5-dev would take over hdf5.pc and bring a second one). python3-h5py: the
# independent reader the tests use to check the exported files.
packages=(libpetsc-real3.18-dev libopenblas0-serial libclang-dev pkg-config openmpi-bin gmsh python3 python3-pip
  libhdf5-mpi-dev python3-h5py)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  $SUDO apt-get update -q >&2
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
fi

# Python meshio and h5py: the independent readers the tests use to check solution.vtu and the
# FCLIB export, for the python3 on PATH (h5py from PyPI when that is not Debian's python3, which
# python3-h5py serves).
for module in meshio h5py; do
  if ! python3 -c "import $module" 2>/dev/null; then
    echo "setup: installing Python $module" >&2
    python3 -m pip install -q "$module" >&2 2>/dev/null \
      || python3 -m pip install -q --user "$module" >&2 2>/dev/null \
      || python3 -m pip install -q --break-system-packages "$module" >&2
  fi
done
