#!/usr/bin/env bash
# Proves that a change leaves every output bit as it was: renders the same matrix of images
# with two vkpath binaries (e.g. one built from the commit before a change and one from the
# change) on this machine, and compares them: EXR pixels bit for bit with the new binary's
# `vkpath compare --exact` (headers carry each render's metadata, which may change), PNG
# files byte for byte.
# Usage: scripts/same-images.sh OLD_VKPATH NEW_VKPATH [WORK_DIR]
# Matrix: the built-in Cornell box and tests/data/emissive_quad.gltf; every integrator; both
# samplers (for the importance-sampled integrators); both traversals (bvh and none); both
# pixel filters; and the workshop's exercise pictures. Small images, few samples.
set -euo pipefail
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d)}
top=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work/old" "$work/new"
gltf="$top/tests/data/emissive_quad.gltf"
cases=()
for scene in builtin gltf; do
  for integrator in workshop cosine nee mis; do
    samplers=(pcg)
    [ "$integrator" = workshop ] || samplers=(pcg sobol)
    for sampler in "${samplers[@]}"; do
      for accel in bvh none; do
        for filter in box center; do
          cases+=("$scene $integrator $sampler $accel $filter")
        done
      done
    done
  done
done
compared=0
differ=0
for case in "${cases[@]}"; do
  read -r scene integrator sampler accel filter <<<"$case"
  name="$scene-$integrator-$sampler-$accel-$filter.exr"
  args=(render --width 24 --height 16 --spp 8 --integrator "$integrator" --accel "$accel" --pixel-filter "$filter" --seed 3)
  [ "$integrator" = workshop ] || args+=(--sampler "$sampler")
  [ "$scene" = gltf ] && args+=("$gltf")
  for side in old new; do
    binary=$old; [ $side = new ] && binary=$new
    "$binary" "${args[@]}" -o "$work/$side/$name" >/dev/null 2>&1
  done
  compared=$((compared + 1))
  if ! "$new" compare --exact "$work/old/$name" "$work/new/$name" >/dev/null 2>&1; then
    echo "DIFFERENT: $name"
    differ=$((differ + 1))
  fi
done
for exercise in ray-tracing sample-sphere sample-hemisphere spherical-coords direct-illumination path-tracing; do
  name="exercise-$exercise.png"
  for side in old new; do
    binary=$old; [ $side = new ] && binary=$new
    "$binary" exercise "$exercise" -o "$work/$side/$name" >/dev/null 2>&1
  done
  compared=$((compared + 1))
  if ! cmp -s "$work/old/$name" "$work/new/$name"; then
    echo "DIFFERENT: $name"
    differ=$((differ + 1))
  fi
done
echo "$compared images compared bit for bit in $work: $((compared - differ)) identical, $differ different"
[ "$differ" -eq 0 ]
