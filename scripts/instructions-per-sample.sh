#!/usr/bin/env bash
# Counts the instructions that lavapipe executes per sample of a render, with valgrind's
# callgrind (an instruction count, repeatable whatever else the machine is doing, unlike
# seconds on a shared machine). Renders the scene twice at 64x64, with 8 and with 72 spp, one
# lavapipe thread, no shader cache, and divides the difference (the 64 extra samples of 4096
# pixels) by 64 * 4096: set-up and kernel compilation cancel out.
# Usage: scripts/instructions-per-sample.sh VKPATH INTEGRATOR [render arguments...]
# e.g.   scripts/instructions-per-sample.sh target/release/vkpath mis --light-sampling area
# Needs valgrind (apt-get install valgrind). About 30 s per render on this 2-core machine.
set -euo pipefail
vkpath=$1
integrator=$2
shift 2
export LP_NUM_THREADS=1 MESA_SHADER_CACHE_DISABLE=true
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
count() {
  local spp=$1
  shift
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$vkpath" render --integrator "$integrator" \
    --sampler pcg --width 64 --height 64 --spp "$spp" "$@" -o "$work/image.exr" 2>&1 |
    sed -n 's/.*I *refs: *//p' | tr -d ,
}
few=$(count 8 "$@")
many=$(count 72 "$@")
echo "$integrator $*: $(( (many - few) / (64 * 64 * 64) )) instructions per sample"
