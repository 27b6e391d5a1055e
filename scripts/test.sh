#!/usr/bin/env bash
# Runs the whole test suite (unit, GPU-vs-CPU, statistical and CLI tests on lavapipe),
# installing what it needs first; then the Python package's tests (python/test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --python
# Mesa 25's lavapipe, unpacked apart (never installed): the driver of the ray-query tests
# alone (tests/ray_query_cli.rs gives it to their vkpath processes through VK_DRIVER_FILES);
# every other test runs on the system's Mesa 22.3. A failed download fails the suite.
ray_query_icd=$(bash scripts/mesa25.sh)
export VKPATH_RAY_QUERY_ICD="$ray_query_icd"
# A toolchain that install-deps.sh put there (none was found).
export PATH="$HOME/.cargo/bin:$PATH"
cargo test --all-targets "$@"
# The doc tests (the crate documentation renders a few samples); --all-targets leaves them out.
cargo test --doc "$@"
# The crate packages: `cargo package --list` succeeds and ships the licence.
packaged=$(cargo package --list --allow-dirty)
if ! grep -qx LICENSE <<<"$packaged"; then
  echo "cargo package --list does not list LICENSE" >&2
  exit 1
fi
# The Python package (python/): `pip install ./python` into a fresh venv, then its pytest tests.
bash python/test.sh
