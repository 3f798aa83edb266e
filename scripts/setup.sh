#!/usr/bin/env bash
# Installs the Debian 12 packages cifs needs, only those that are missing.
# Usage: scripts/setup.sh            (uses sudo when not root)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config  # Ninja: compiles start before the libraries they need are linked
  libeigen3-dev libboost-graph-dev libopenexr-dev catch2
  nlohmann-json3-dev libcli11-dev libpng-dev libbenchmark-dev
  python3-dev pybind11-dev python3-numpy python3-matplotlib  # the cifs Python package and its examples
  libosd-dev libopenmesh-dev  # OpenSubdiv, OpenMesh: oracles of the mesh subdivision tests only
  libsisl-dev  # AGPL comparator: linked into bench/ only, never into the library
  libcgal-dev  # GPL cross-check of the mesh schemes (tests/subdivision/test_mesh_cgal.cpp) only
  libopenmpi-dev openmpi-bin  # cifs render across processes (-DCIFS_MPI=ON, on in the presets)
  python3-mpi4py  # examples/python/sweep.py across processes under mpirun (optional: one process without)
  clang-format clang-tidy  # scripts/lint.sh (CI)
  chromium  # headless browser of the gallery page's test (tests/gallery/test_index.py)
  libcpp-httplib-dev  # cifs view's HTTP server (MIT; Debian builds it as a shared library beside the header)
  libjs-three  # three.js r111 for cifs view's page, served from the machine and copied by --export (no CDN)
  chromium-driver python3-selenium  # the browser tests driven like a user: tests/view/test_view.py, tests/gallery/test_index.py
  libocct-data-exchange-dev  # OpenCASCADE (LGPL, dynamic): STEP and IGES in the optional cifs::occt (-DCIFS_OCCT); 23 packages, 37 MB, 183 MB installed
  libtbb-dev  # libtbb.so, which Debian's OpenCASCADE CMake package names without depending on it
  libclang-rt-14-dev  # libFuzzer and the sanitizer runtimes of clang 14: scripts/fuzz.sh (the fuzz preset)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
