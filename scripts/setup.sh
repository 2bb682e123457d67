#!/usr/bin/env bash
# Installs the Debian packages gonio needs to build and test, only when one is missing.
# Idempotent and non-interactive: safe to run on every build, in CI and on a fresh machine.
set -euo pipefail

packages=(
  cmake g++ make ninja-build pkg-config
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libcli11-dev
  libpugixml-dev            # MaterialX documents (.mtlx): {"mtlx": ...} and gonio materials --from-mtlx
  libceres-dev              # gonio fit (GONIO_BUILD_FIT)
  libembree-dev libtbb-dev libopenexr-dev libpng-dev libtinyobjloader-dev
  libfftw3-dev              # gonio measure: Gaussian random height fields
  libopenimageio-dev        # textures and environment maps in any format (PNG, JPEG, EXR, HDR, TIFF)
  libtinygltf-dev           # glTF 2.0 scenes (gonio render scene.gltf|.glb)
  libcpp-httplib-dev        # gonio explore: the HTTP server of the explorer (GONIO_BUILD_EXPLORE)
  chromium                  # gonio explore's browser tests (headless; tests/explore)
  clang libclang-rt-14-dev  # libFuzzer and the sanitizer runtimes of the fuzz pass
  binutils                  # strings: the consumer test checks the installed files for build paths
  dpkg-dev file             # cpack -G DEB: dpkg-shlibdeps computes Depends, file finds the ELF files
  pybind11-dev python3-dev python3-numpy  # the Python module (python/, docs/python.md)
  python3-matplotlib python3-pytest       # gonio.plot and the module's tests
  python3-dask python3-distributed        # gonio.distributed: renders and fits on a Dask cluster (docs/distributed.md)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo -n)
  else
    echo "setup: missing packages (${missing[*]}) and not root; install them or run as root" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
