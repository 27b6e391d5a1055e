#!/usr/bin/env bash
# Installs the Python package into a fresh virtual environment (target/python-venv) the way a
# user does, `pip install ./python` (pip fetches maturin and numpy from PyPI), and runs its
# tests (python/tests) against the command line's binary, target/debug/vkpath.
#
# The extension is built with Cargo's `test` profile, the one `cargo test` builds vkpath and
# its dependencies with, so after `cargo test` only pyo3 and the extension itself compile
# (users' `pip install ./python` builds the release profile).
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/python-venv
rm -rf "$venv"
python3 -m venv "$venv"
MATURIN_PEP517_ARGS="--profile test" "$venv/bin/pip" install --quiet "./python[test]"
# The command line the tests compare with (already built by `cargo test`; a no-op then).
cargo build --profile test --bin vkpath --quiet
VKPATH_CLI="$(pwd)/target/debug/vkpath" "$venv/bin/python" -m pytest -q python/tests "$@"
