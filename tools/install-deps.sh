#!/usr/bin/env bash
# Installs every Debian 12 package that sarmap's build, tests and benchmarks
# need. Idempotent: packages already present are left as they are.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # library
  libeigen3-dev libtbb-dev libembree-dev libxsimd-dev nlohmann-json3-dev
  libpng-dev libassimp-dev zlib1g-dev
  # command-line tool
  libcli11-dev
  # tests and benchmarks (OctoMap is a peer compared against, not a dependency)
  libgtest-dev libgmock-dev libbenchmark-dev liboctomap-dev
  # tests only: Boost Graph Library's Kruskal, compared against in tests/topo
  libboost-graph-dev
  # tests only: graph.json must load in networkx (tests/cli/plan_command_test.cpp)
  python3-networkx
  # ROS 1 bags in (engine/io_rosbag, optional: built when found): rosbag_storage
  # reads the bag container; the test writes its bags with python3-rosbag
  # (tests/cli/rosbag_input_test.cpp). librosbag-dev (player, recorder) is not needed.
  librosbag-storage-dev python3-rosbag
  # fuzzing only (fuzz/, tools/fuzz.sh, the CI fuzz job): clang and its
  # libFuzzer runtime; GCC has no libFuzzer
  clang-14 libclang-rt-14-dev
  # the browser viewer (`sarmap view`): Node.js runs npm and esbuild (web/),
  # and its test drives Debian's Chromium (tests/viewer/)
  nodejs chromium
  # the Python module (python/, docs/python.md): pybind11 builds it for
  # Debian's python3 (python3-dev's headers); numpy is its array type, and
  # pytest runs its suite (tests/python/)
  pybind11-dev python3-dev python3-numpy python3-pytest
  # sarmap.distributed (python/sarmap/distributed.py) and its test: Dask's
  # distributed scheduler
  python3-distributed
)

# Optional (--python): Debian's PyTorch with OpenBLAS, needed only by
# tools/python/dgcnn_reference.py, export_safetensors.py and the PyTorch peer
# benchmark (bench/peers); the build, the tests and CI do not need them.
if [[ "${1:-}" == "--python" ]]; then
  packages+=(python3-torch libopenblas0-pthread)
  shift
fi

if [[ "${1:-}" == "--list" ]]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# The viewer's npm packages (three, esbuild, playwright-core), pinned by
# web/package-lock.json into web/node_modules; never kept in the repository.
install_npm_packages() {
  local web
  web="$(cd "$(dirname "$0")/.." && pwd)/web"
  if ! command -v npm >/dev/null 2>&1; then
    echo "install-deps: npm not found; installing Debian's npm"
    $SUDO apt-get install -y --no-install-recommends npm
  fi
  if [[ -f "$web/node_modules/.package-lock.json" && "$web/node_modules/.package-lock.json" -nt "$web/package-lock.json" ]]; then
    echo "install-deps: web/node_modules is up to date"
    return
  fi
  echo "install-deps: npm ci in web/"
  (cd "$web" && npm ci --no-audit --no-fund)
}

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  SUDO=$([[ $(id -u) -ne 0 ]] && echo sudo || true)
  install_npm_packages
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO=sudo
  else
    echo "install-deps: not root and no sudo; run as root:" >&2
    echo "  apt-get update && apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
else
  SUDO=
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
install_npm_packages
