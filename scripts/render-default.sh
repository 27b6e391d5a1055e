#!/usr/bin/env bash
# Renders the built-in scene (the workshop's Cornell box) to cornell.png, installing what it
# needs first. Extra arguments go to `vkpath render`, e.g. --spp 1024 or -o cornell.exr.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
# A toolchain that install-deps.sh put there (none was found).
export PATH="$HOME/.cargo/bin:$PATH"
cargo run --release --quiet -- render -o cornell.png --width 512 --height 512 --spp 256 "$@"
echo "wrote $(pwd)/cornell.png" >&2
