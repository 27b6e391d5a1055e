#!/usr/bin/env bash
# Runs the whole test suite (unit, GPU-vs-CPU, statistical and CLI tests on lavapipe),
# installing what it needs first.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cargo test --all-targets "$@"
# The doc tests (the crate documentation renders a few samples); --all-targets leaves them out.
cargo test --doc "$@"
