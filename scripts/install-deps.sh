#!/usr/bin/env bash
# Installs the Debian 12 packages vkpath needs, when they are missing (run as root):
# the Vulkan loader, lavapipe (Mesa's CPU Vulkan driver), the validation layers, and the
# shaderc / glslang / SPIRV-Tools static libraries that build.rs links; then Intel Open Image
# Denoise for `--denoise` (scripts/install-oidn.sh: not a Debian package).
set -euo pipefail
packages=(libvulkan1 mesa-vulkan-drivers vulkan-validationlayers libshaderc-dev glslang-dev spirv-tools)
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq "${missing[@]}" >/dev/null
fi
bash "$(dirname "$0")/install-oidn.sh"
if ! command -v cargo >/dev/null; then
  echo "cargo is missing: install a Rust toolchain (1.89 or newer) first" >&2
  exit 1
fi
