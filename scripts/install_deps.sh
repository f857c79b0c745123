#!/usr/bin/env bash
# Installs the Debian 12 (bookworm) packages this project builds and tests with.
# Idempotent: when every package is already installed it touches nothing (no apt-get update), so
# repeated runs take well under a second. Needs root, or sudo when run as another user.
set -euo pipefail

# The one list of packages. Add new dependencies here.
PACKAGES=(
  build-essential
  cmake
  ninja-build
  pkg-config
  git
  libgmp-dev
  libcgal-dev
  nlohmann-json3-dev
  libcli11-dev
  libgtest-dev
  libembree-dev
  libtbb-dev
  libopenmesh-dev
  libtinygltf-dev
  libstb-dev
  libopenexr-dev
  libglfw3-dev
  libglm-dev
  libimgui-dev
  libosmesa6-dev
  libegl-dev
  libgl1-mesa-dri
  python3-matplotlib
  xvfb
  xauth
  xdotool
  imagemagick
  clang
  libclang-rt-14-dev
  libopenmpi-dev
  openmpi-bin
)

is_installed() {
  # dpkg-query prints e.g. "install ok installed"; anything else (absent, config-files, half
  # installed) means the package still has to be installed.
  [[ "$(dpkg-query -W -f='${Status}' "$1" 2>/dev/null || true)" == "install ok installed" ]]
}

missing=()
for pkg in "${PACKAGES[@]}"; do
  is_installed "$pkg" || missing+=("$pkg")
done

if ((${#missing[@]} == 0)); then
  echo "install_deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
echo "install_deps: missing: ${missing[*]}"

as_root=()
if [[ "$(id -u)" -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
  else
    echo "install_deps: not root and no sudo: install these packages by hand: ${missing[*]}" >&2
    exit 1
  fi
fi

"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y --no-install-recommends "${PACKAGES[@]}"

for pkg in "${PACKAGES[@]}"; do
  if ! is_installed "$pkg"; then
    echo "install_deps: $pkg is still not installed" >&2
    exit 1
  fi
done
echo "install_deps: done"
