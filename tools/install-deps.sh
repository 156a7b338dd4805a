#!/usr/bin/env bash
# Installs xcut's build and test dependencies from Debian 12's packages (run as root).
# Every library comes from Debian; nothing is vendored or downloaded from elsewhere.
# libopenblas0-serial: CHOLMOD's supernodal factor and solve run on BLAS; the reference BLAS Debian
# installs otherwise is several times slower. The serial build keeps BLAS off the second core (the
# engine's own threads are OpenMP's) and its results independent of the thread count.
# gmsh, python3-meshio, python3-vtk9: the tests write mesh files with the real programs and read them;
# python3-jsonschema checks every scene against docs/scene.schema.json.
# libglfw3-dev, libimgui-dev, libepoxy-dev: `xcut view` (optional: the build leaves it out without them);
# xvfb, xauth, xdotool, libgl1-mesa-dri: its tests open the window on a virtual display with software
# OpenGL and drag the mouse on it.
# libopenigtlink-dev: the OpenIGTLink tool device and xcut-igtl-play (optional like the viewer).
# python3-dev, pybind11-dev, python3-numpy: the Python module (import xcut, docs/python.md);
# python3-pytest: its tests; python3-distributed: `python3 -m xcut.sweep` on dask.
# calculix-ccx: the accuracy suite's independent references (quadratic elements; optional: without it the
# suite scores against beam theory, a linear-tet reference and the handbook, and says so).
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
  build-essential cmake ninja-build pkg-config git \
  libeigen3-dev libembree-dev libfcl-dev libccd-dev \
  nlohmann-json3-dev libcli11-dev libfmt-dev libspdlog-dev \
  libgtest-dev libgmock-dev libbenchmark-dev libtet1.5-dev \
  zlib1g-dev libpugixml-dev libpng-dev libstb-dev python3 python3-matplotlib \
  libsuitesparse-dev libopenblas0-serial clang-14 libclang-rt-14-dev libomp-14-dev \
  gmsh python3-meshio python3-vtk9 python3-jsonschema \
  libglfw3-dev libimgui-dev libepoxy-dev xvfb xauth xdotool libgl1-mesa-dri libopenigtlink-dev \
  calculix-ccx python3-dev pybind11-dev python3-numpy python3-pytest python3-distributed
