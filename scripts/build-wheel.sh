#!/usr/bin/env bash
# Builds the Python package as one abi3 wheel (any CPython >= 3.9 on this platform) into
# dist/, with maturin in a build venv (target/wheel-venv; pip fetches maturin from PyPI once):
#
#   bash scripts/build-wheel.sh
#   pip install dist/vkpath-*.whl        # seconds, where `pip install ./python` compiles
#
# The wheel holds the release build of the extension (vkpath and its shader compiler are
# linked in; at run time it needs the Vulkan loader and a driver, as the binary does).
# Build it on the oldest system you install it on (glibc); `--compatibility manylinux...`
# can be passed through as extra arguments to `maturin build`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/wheel-venv
if [ ! -x "$venv/bin/maturin" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet "maturin>=1.9.4,<2"
fi
mkdir -p dist
"$venv/bin/maturin" build --release --manifest-path python/Cargo.toml --out dist "$@"
ls -l dist/vkpath-*.whl
