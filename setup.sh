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
packages=(libpetsc-real3.18-dev libopenblas0-serial libclang-dev pkg-config openmpi-bin gmsh python3 python3-pip)

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

# Python meshio: the independent reader the tests use to check solution.vtu.
if ! python3 -c "import meshio" 2>/dev/null; then
  echo "setup: installing Python meshio" >&2
  python3 -m pip install -q meshio >&2 2>/dev/null \
    || python3 -m pip install -q --user meshio >&2 2>/dev/null \
    || python3 -m pip install -q --break-system-packages meshio >&2
fi
