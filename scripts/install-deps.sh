#!/usr/bin/env bash
# Installs everything ssvgi needs to build, run and test, from Debian 12 packages only. Idempotent: a second run
# installs nothing new.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libvulkan-dev vulkan-validationlayers mesa-vulkan-drivers vulkan-tools glslc spirv-tools
  libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libtinyexr-dev zlib1g-dev libcli11-dev
  libgtest-dev
  libglfw3-dev libimgui-dev xvfb xauth
)

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
