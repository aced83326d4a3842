#!/usr/bin/env bash
# Configures and builds Metamer in build/ (Release with debug info), then makes the Python package
# from that same build tree, the way `pip install .` makes it (pyproject.toml, scikit-build-core;
# nothing is compiled twice), into build/dist/, and installs that wheel into the project's venv:
# the venv's `import metamer` and `metamer` command are what a user's pip installs (docs/python.md).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build "$here/build" -j "$(nproc)"
rm -f "$here"/build/dist/metamer-*.whl
# The build tree's own settings (tests on, RelWithDebInfo) so scikit-build-core's configure keeps
# them and adds only the install rules (SKBUILD).
"$here/.venv/bin/pip" wheel --quiet --disable-pip-version-check --no-build-isolation --no-deps \
  --config-settings=build-dir="$here/build" --config-settings=cmake.build-type=RelWithDebInfo \
  --config-settings=cmake.define.METAMER_BUILD_TESTS=ON \
  -w "$here/build/dist" "$here"
"$here/.venv/bin/pip" install --quiet --disable-pip-version-check --no-deps --force-reinstall "$here"/build/dist/metamer-*.whl
