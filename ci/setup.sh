#!/usr/bin/env bash
# Installs everything Metamer needs on Debian 12 (bookworm): the build tools, Vulkan with Mesa's
# lavapipe software rasterizer and the validation layers, the libraries, clang with libFuzzer (for
# ci/fuzz.sh), and a Python virtual environment with colour-science (the independent oracle some
# tests use). Runs as root; safe to run again (apt-get and pip skip what is already there).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools
  libglm-dev libeigen3-dev libfmt-dev nlohmann-json3-dev libcli11-dev libtinygltf-dev
  libopenexr-dev libpng-dev libtiff-dev libopenimageio-dev openimageio-tools
  libglfw3-dev libimgui-dev xvfb fonts-dejavu-core
  libgtest-dev libssl-dev libhdf5-dev liblcms2-dev pybind11-dev libfftw3-dev
  slurmctld slurmd slurm-client munge
  clang libclang-rt-14-dev
  python3 python3-dev python3-venv python3-pip python3-openimageio python3-numpy python3-pytest
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Debian's python3 sees python3-openimageio; the venv inherits it (--system-site-packages) and
# adds colour-science from PyPI, pinned so the oracle does not move under the tests, and pandas
# (the reader the batch index is tested with; Debian's python3-pandas is built for Debian's numpy,
# not the venv's, and would break colour-science's import).
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
# h5py and Spectral Python are the readers the HDF5 and ENVI outputs are tested with (Debian's
# python3-h5py is built for Debian's numpy, as pandas is). numpy is pinned so the oracle's and the
# readers' numpy is the one the tests were written against.
pip_in_venv=("$venv/bin/pip" install --quiet --disable-pip-version-check)
if ! "$venv/bin/python" -c "import numpy; assert numpy.__version__ == '2.2.6'" 2>/dev/null; then
  "${pip_in_venv[@]}" "numpy==2.2.6"
fi
if ! "$venv/bin/python" -c "import colour" 2>/dev/null; then
  "${pip_in_venv[@]}" "colour-science==0.4.7" "numpy==2.2.6"
fi
if ! "$venv/bin/python" -c "from pandas import Series" 2>/dev/null; then
  "${pip_in_venv[@]}" "pandas==2.2.3" "numpy==2.2.6"
fi
if ! "$venv/bin/python" -c "import h5py, spectral" 2>/dev/null; then
  "${pip_in_venv[@]}" "h5py==3.13.0" "spectral==0.24" "numpy==2.2.6"
fi
# matplotlib draws the camera report's plots (metamer.camera_report, docs/camera.md). Debian's
# python3-matplotlib is built for Debian's numpy 1.x, not the pinned 2.2.6: pip's wheel instead.
if ! "$venv/bin/python" -c "import matplotlib" 2>/dev/null; then
  "${pip_in_venv[@]}" "matplotlib==3.10.3" "numpy==2.2.6"
fi
# mat73 reads MATLAB v7.3 files as the ARAD / NTIRE challenge's users do (tests/python/test_arad.py).
if ! "$venv/bin/python" -c "import mat73" 2>/dev/null; then
  "${pip_in_venv[@]}" "mat73==0.65" "numpy==2.2.6"
fi
# OpenEXR's own Python binding (the ASWF's) reads the ground truth's ids, depth and normal as a
# learner's loader does (docs/io.md, "Ground truth"; tests/python/test_ground_truth.py).
if ! "$venv/bin/python" -c "import OpenEXR" 2>/dev/null; then
  "${pip_in_venv[@]}" "OpenEXR==3.5.3" "numpy==2.2.6"
fi
# tmm (Byrnes' transfer-matrix method) is the independent oracle for the dielectric slabs.
if ! "$venv/bin/python" -c "import tmm" 2>/dev/null; then
  "${pip_in_venv[@]}" "tmm==0.2.0" "numpy==2.2.6"
fi
# scipy solves the two-flux equations for the Kubelka–Munk oracle (tests/python/check_kubelka_munk.py).
if ! "$venv/bin/python" -c "import scipy.integrate" 2>/dev/null; then
  "${pip_in_venv[@]}" "scipy==1.17.1" "numpy==2.2.6"
fi
# colour-demosaicing: the oracle for the simulated sensor's Bayer mosaic (tests/python/test_sensor.py).
if ! "$venv/bin/python" -c "import colour_demosaicing" 2>/dev/null; then
  "${pip_in_venv[@]}" "colour-demosaicing==0.2.7" "colour-science==0.4.7" "numpy==2.2.6"
fi
# rawpy (LibRaw): the reader that checks the simulated sensor's DNG files (tests/python/test_sensor.py).
if ! "$venv/bin/python" -c "import rawpy" 2>/dev/null; then
  "${pip_in_venv[@]}" "rawpy==0.28.0" "numpy==2.2.6"
fi
# scikit-build-core: the build backend of pyproject.toml, which ci/build.sh runs without build
# isolation (the wheel is made from build/, and pip would otherwise fetch it for every build).
if ! "$venv/bin/python" -c "import scikit_build_core; assert scikit_build_core.__version__ == '1.1.2'" 2>/dev/null; then
  "${pip_in_venv[@]}" "scikit-build-core==1.1.2"
fi
# xarray (with h5netcdf) opens the HDF5 cubes — their named dimensions are checked by
# tests/python/check_cube_formats.py and check_ordinary_tools.py — and Render.to_xarray's arrays;
# mypy checks a user's script against the package's types (tests/python/test_typing.py).
if ! "$venv/bin/python" -c "import xarray, h5netcdf, mypy" 2>/dev/null; then
  "${pip_in_venv[@]}" "xarray==2025.6.1" "h5netcdf==1.6.4" "mypy==1.15.0" "numpy==2.2.6"
fi
echo "metamer: set-up complete"
