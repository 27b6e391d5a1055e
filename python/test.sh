#!/usr/bin/env bash
# Installs the Python package into a fresh virtual environment (target/python-venv) the way a
# user does, `pip install ./python` (pip fetches maturin and numpy from PyPI), and runs its
# tests (python/tests) against the command line's binary, target/debug/vkpath.
#
# The extension is built with Cargo's `dev` profile, whose settings are the `test`
# profile's (Cargo.toml), and Cargo.toml names the features pyo3 turns on in shared crates
# (held by `house::the_python_extension_resolves_the_features_vkpath_is_tested_with`), so after
# `cargo test` its dependencies and the vkpath library itself are reused (not the `test`
# profile itself: maturin builds with `cargo rustc`, which with `--profile test` makes a test
# harness, not a library). Users' `pip install ./python` builds the release profile.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/python-venv
# Kernel pipelines are cached in a temporary folder, never in the home directory.
export VKPATH_CACHE_DIR="${TMPDIR:-/tmp}/vkpath-tests-pipeline-cache"
rm -rf "$venv"
python3 -m venv "$venv"
MATURIN_PEP517_ARGS="--profile dev" "$venv/bin/pip" install --quiet "./python[test]"
# The command line the tests compare with: VKPATH_CLI, else target/debug/vkpath as `cargo
# test` builds it (an integration test's build brings the binary with the same features, so
# after `cargo test` this is a no-op; `cargo build --bin` would rebuild the library without
# the dev-dependencies' features).
if [ -z "${VKPATH_CLI:-}" ]; then
  cargo test --no-run --quiet --test cli
  VKPATH_CLI="$(pwd)/target/debug/vkpath"
fi
VKPATH_CLI="$VKPATH_CLI" "$venv/bin/python" -m pytest -q python/tests "$@"
