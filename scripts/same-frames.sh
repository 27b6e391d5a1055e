#!/usr/bin/env bash
# Proves that a change to how `render --frames` sets up its frames leaves every frame as it
# was: renders the same sequences with two vkpath binaries (e.g. the one before a change and
# the one after) and compares every frame's EXR pixels bit for bit (`vkpath compare
# --exact` of the new binary). Sequences: tests/data/skinned_morphed.gltf (plain; in tiles;
# guided; compressed BVH; no BVH), tests/data/RiggedSimple.gltf (a side view and its own
# framing, which follows the moving bounds; and on two devices, `--device 0,0`),
# tests/data/BoxAnimated.gltf and tests/data/SimpleMorph.gltf (Khronos' keyframed and
# morphed samples), scenes/materials.gltf with a sphere sliding (textured: its geometry
# moves, its materials and textures do not; scripts/make_moving_scenes.py), RiggedSimple lit
# by an environment map (an EXR of the Cornell box the old binary renders), the Cornell box,
# tests/data/emissive_quad.gltf and `--generated 100000` (static). A render that fails counts
# as different.
# Usage: scripts/same-frames.sh OLD_VKPATH NEW_VKPATH [WORK_DIR]
set -euo pipefail
# As scripts/same-images.sh: both binaries compile every kernel afresh (llvmpipe's kernels
# from Mesa's shader cache can differ in the last bits from those compiled in the process).
export MESA_SHADER_CACHE_DISABLE=true
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d)}
root=$(cd "$(dirname "$0")/.." && pwd)
data=$root/tests/data
mkdir -p "$work"
python3 "$root/scripts/make_moving_scenes.py" slide "$root/scenes/materials.gltf" "sphere gold" \
  "$work/moving_materials.gltf" >/dev/null
"$old" render --width 64 --height 32 --spp 4 --quiet -o "$work/environment.exr"
small=(--width 64 --height 48 --spp 8 --quiet)
sequences=(
  "sk $data/skinned_morphed.gltf --frames 0..8 --fps 8"
  "skt $data/skinned_morphed.gltf --frames 0..4 --fps 4 --tile-size 16"
  "skg $data/skinned_morphed.gltf --frames 0..3 --fps 4 --guiding"
  "skc $data/skinned_morphed.gltf --frames 0..3 --fps 4 --accel compressed-bvh"
  "skn $data/skinned_morphed.gltf --frames 0..3 --fps 4 --accel none"
  "rs $data/RiggedSimple.gltf --frames 0..8 --fps 4 --camera-position 18,0,0 --look-at 0,0,0"
  "rsf $data/RiggedSimple.gltf --frames 0..4 --fps 4"
  "rsd $data/RiggedSimple.gltf --frames 0..4 --fps 4 --device 0,0"
  "ba $data/BoxAnimated.gltf --frames 0..6 --fps 1.6 --camera-position 2.8,2.7,3.9 --look-at 0,1.5,0"
  "sm $data/SimpleMorph.gltf --frames 0..5 --fps 1.5 --camera-position 0.5,1.25,4.2 --look-at 0.5,1.25,0"
  "mm $work/moving_materials.gltf --frames 0..3 --fps 2"
  "rse $data/RiggedSimple.gltf --frames 0..3 --fps 3 --environment $work/environment.exr"
  "cb --frames 0..3"
  "eq $data/emissive_quad.gltf --frames 0..3"
  "gen --generated 100000 --frames 0..3"
)
for side in old new; do
  mkdir -p "$work/$side"
  binary=$old
  [ "$side" = new ] && binary=$new
  for sequence in "${sequences[@]}"; do
    read -r name args <<<"$sequence"
    light=(--background 1,1,1)
    [[ $args == *--environment* ]] && light=()
    # shellcheck disable=SC2086
    "$binary" render $args "${small[@]}" "${light[@]}" -o "$work/$side/${name}_####.exr" ||
      echo "$side: $name failed"
  done
done
compared=0
different=0
for file in "$work"/old/*.exr; do
  name=$(basename "$file")
  compared=$((compared + 1))
  if ! "$new" compare --exact "$file" "$work/new/$name" >/dev/null 2>&1; then
    echo "different: $name"
    different=$((different + 1))
  fi
done
echo "$compared frames compared, $different different ($work)"
[ "$different" -eq 0 ] && [ "$compared" -gt 0 ]
