#!/usr/bin/env bash
# Where a guided render's training spends its seconds on a GPU (issue 22): the opening scene
# at 640x480, 256 spp, 8 vertices, `--guiding`, rendered four times (the first fills the
# caches), each printing its guide line "trained on ... in S s (pipeline P s, frames F s,
# host H s)" and the whole process's wall and CPU seconds; plain `mis` twice for comparison;
# then the built-in Cornell box at 256x256 (a small image, where training's host side shows)
# guided three times.
# Run like scripts/gpu-bench.sh (same carry: .gl with the loader debs, .gpu/vkpath):
#   run(command="bash scripts/gpu-guide-times.sh", carry=[".gl", ".gpu"], timeout_s=240)
# On lavapipe, `bash scripts/gpu-guide-times.sh --small target/release/vkpath` runs it at 80x60
# without --require-gpu (a check of the script, not a measurement).
set -uo pipefail

size=(--width 640 --height 480)
gpu=(--require-gpu)
if [ "${1:-}" = "--small" ]; then
    size=(--width 80 --height 60)
    gpu=()
    shift
fi
bin=${1:-.gpu/vkpath}
if ! ldconfig -p | grep 'libvulkan\.so\.1' >/dev/null && ls .gl/*.deb >/dev/null 2>&1; then
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
fi
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$icd" ]; then
    export VK_DRIVER_FILES=$icd
fi
export VKPATH_CACHE_DIR=$(mktemp -d)
common=(render scenes/opening.gltf "${size[@]}" --spp 256 --max-path-length 8 --integrator mis
        "${gpu[@]}" -o /tmp/guide-times.exr)
# bash's own `time` (the device machine has no /usr/bin/time): the process's wall and CPU seconds.
TIMEFORMAT="process: %R s wall, %U s user, %S s system"
for run in 1 2 3 4; do
    echo "== guided, run $run"
    { time timeout 60 "$bin" "${common[@]}" --guiding 2>&1 | grep -E "trained on|setup"; } 2>&1
done
for run in 1 2; do
    echo "== plain mis, run $run"
    { time timeout 60 "$bin" "${common[@]}" 2>&1 | grep -E "setup"; } 2>&1
done
for run in 1 2 3; do
    echo "== Cornell box 256x256, guided, run $run"
    { time timeout 60 "$bin" render --width 256 --height 256 --spp 256 --integrator mis --guiding \
        "${gpu[@]}" -o /tmp/guide-times-box.exr 2>&1 | grep -E "trained on|setup"; } 2>&1
done
