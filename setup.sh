#!/usr/bin/env bash
# Installs every system package signorini needs on Debian 12 (PETSc 3.18 with MUMPS and hypre,
# libclang for bindgen, Open MPI, Gmsh) and Python meshio for the tests. Idempotent and quiet
# when everything is already there. Uses sudo when not run as root.
set -euo pipefail

packages=(libpetsc-real3.18-dev libclang-dev pkg-config openmpi-bin gmsh python3 python3-pip)

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
