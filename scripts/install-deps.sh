#!/usr/bin/env bash
# Installs the Debian 12 packages vkpath needs, when they are missing (run as root):
# the Vulkan loader, lavapipe (Mesa's CPU Vulkan driver), the validation layers, and the
# shaderc / glslang / SPIRV-Tools static libraries that build.rs links; then Intel Open Image
# Denoise for `--denoise` (scripts/install-oidn.sh: not a Debian package); then, where no
# cargo is found, a Rust toolchain by rustup into ~/.cargo (Debian 12's rustc 1.63 is older
# than the 1.89 the dependencies need). Callers put ~/.cargo/bin on their PATH. With
# --python, also what the Python package's tests need.
set -euo pipefail
packages=(libvulkan1 mesa-vulkan-drivers vulkan-validationlayers libshaderc-dev glslang-dev spirv-tools)
# The C toolchain Rust links with, and what fetches rustup.
packages+=(gcc libc6-dev curl ca-certificates)
# --python (scripts/test.sh): also Python 3 with venv, to build and test python/ in a
# virtual environment (pip brings maturin and numpy from PyPI; no python3-dev is needed:
# PyO3 declares the C API itself and an extension module links no libpython).
if [ "${1:-}" = "--python" ]; then
  packages+=(python3 python3-venv)
fi
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
export PATH="$HOME/.cargo/bin:$PATH"
if ! command -v cargo >/dev/null; then
  echo "installing a Rust toolchain (rustup, stable, minimal profile) into ~/.cargo" >&2
  if ! curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs -o /tmp/rustup-init.sh; then
    echo "cannot download rustup from sh.rustup.rs: install a Rust toolchain (1.89 or newer) and run this again" >&2
    exit 1
  fi
  sh /tmp/rustup-init.sh -y --no-modify-path --profile minimal --default-toolchain stable >/dev/null
  rm -f /tmp/rustup-init.sh
fi
