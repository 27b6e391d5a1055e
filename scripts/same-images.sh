#!/usr/bin/env bash
# Proves that a change leaves every output bit as it was: renders the same matrix of images
# with two vkpath binaries (e.g. one built from the commit before a change and one from the
# change) on this machine, and compares them: EXR pixels bit for bit with the new binary's
# `vkpath compare --exact` (headers carry each render's metadata, which may change), PNG
# files byte for byte but for their tEXt chunks (the render's metadata).
# Usage: scripts/same-images.sh OLD_VKPATH NEW_VKPATH [WORK_DIR]
# SAME_IMAGES_SHOWCASE=FILE renders FILE in place of scenes/materials.gltf (e.g. the showcase
# as it was before a change that adds objects to it, to prove the rest unchanged).
# Matrix: the built-in Cornell box and tests/data/emissive_quad.gltf; every integrator; both
# samplers (for the importance-sampled integrators); the traversals (bvh, compressed-bvh with
# the box filter, and none); both
# pixel filters; and the workshop's exercise pictures. Then the material kernels (built
# with USE_MATERIALS): the showcase scenes/materials.gltf with every integrator and both
# samplers, and the scenes of scripts/make_same_images_scenes.py (glossy, textured,
# alpha-masked and blended, environment-map-lit, background-lit, punctual-lit), each with
# every integrator and, between them, both samplers for each (a material kernel takes
# seconds to build on lavapipe, so not every pair for every scene). Then guided renders
# (--guiding: nee and mis on the box, mis on the showcase). Small images, few samples; the
# two binaries render each case at once, one per core. A render that fails counts as
# different (its file is removed before each case). The scenes: scripts/same-images-scenes.sh.
set -euo pipefail
# Both binaries compile every kernel afresh: llvmpipe's kernels loaded from Mesa's shader
# cache can differ in the last bits from the same kernels compiled in the process (material
# kernels, docs/guiding.md "A lavapipe fact"), and a changed build would compile where the
# old one loads.
export MESA_SHADER_CACHE_DISABLE=true
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d)}
top=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work/old" "$work/new"
# shellcheck source=same-images-scenes.sh
source "$top/scripts/same-images-scenes.sh"
cases=()
for scene in builtin gltf; do
  for integrator in workshop cosine nee mis; do
    samplers=(pcg)
    [ "$integrator" = workshop ] || samplers=(pcg sobol)
    for sampler in "${samplers[@]}"; do
      for accel in bvh compressed-bvh none; do
        filters=(box center)
        # The compressed tree's traversal is the filter's business as little as the 4-wide one's
        [ "$accel" = compressed-bvh ] && filters=(box)
        for filter in "${filters[@]}"; do
          cases+=("$scene $integrator $sampler $accel $filter")
        done
      done
    done
  done
done
compared=0
differ=0
# Whether two PNGs are the same file but for their tEXt chunks (render metadata, which a
# change may extend, as the EXR headers' attribute): every other chunk byte for byte.
png_same() {
  python3 - "$1" "$2" <<'PY'
import struct, sys
def chunks(path):
    data = open(path, "rb").read()
    out, at = [data[:8]], 8
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        if data[at + 4:at + 8] != b"tEXt":
            out.append(data[at:at + 12 + length])
        at += 12 + length
    return out
try:
    sys.exit(0 if chunks(sys.argv[1]) == chunks(sys.argv[2]) else 1)
except OSError:
    sys.exit(1)
PY
}
# Renders one case with both binaries (at once) and compares the EXRs' pixels bit for bit.
# Usage: render_both NAME ARGS...
render_both() {
  local name=$1
  shift
  # A failed render must not leave an earlier run's file to be compared.
  rm -f "$work/old/$name" "$work/new/$name"
  "$old" "$@" -o "$work/old/$name" >"$work/old/$name.log" 2>&1 &
  local old_job=$!
  "$new" "$@" -o "$work/new/$name" >"$work/new/$name.log" 2>&1 || true
  wait "$old_job" || true
  compared=$((compared + 1))
  if ! "$new" compare --exact "$work/old/$name" "$work/new/$name" >/dev/null 2>&1; then
    echo "DIFFERENT: $name"
    differ=$((differ + 1))
  fi
}
for case in "${cases[@]}"; do
  read -r scene integrator sampler accel filter <<<"$case"
  args=(render --width 24 --height 16 --spp 8 --integrator "$integrator" --accel "$accel" --pixel-filter "$filter" --seed 3)
  [ "$integrator" = workshop ] || args+=(--sampler "$sampler")
  same_images_scene_args "$scene" "$work"
  render_both "$scene-$integrator-$sampler-$accel-$filter.exr" "${args[@]}"
done
for exercise in ray-tracing sample-sphere sample-hemisphere spherical-coords direct-illumination path-tracing; do
  name="exercise-$exercise.png"
  rm -f "$work/old/$name" "$work/new/$name"
  for side in old new; do
    binary=$old; [ $side = new ] && binary=$new
    "$binary" exercise "$exercise" -o "$work/$side/$name" >/dev/null 2>&1
  done
  compared=$((compared + 1))
  if ! png_same "$work/old/$name" "$work/new/$name"; then
    echo "DIFFERENT: $name"
    differ=$((differ + 1))
  fi
done
# The material kernels.
same_images_make_scenes "$old" "$work"
material_cases=(
  "showcase workshop pcg" "showcase cosine pcg" "showcase cosine sobol" "showcase nee pcg"
  "showcase nee sobol" "showcase mis pcg" "showcase mis sobol"
)
for scene in glossy textured alpha environment punctual; do
  material_cases+=("$scene workshop pcg" "$scene mis pcg" "$scene mis sobol")
  case $scene in
    glossy | alpha | punctual) material_cases+=("$scene cosine pcg" "$scene nee sobol") ;;
    *) material_cases+=("$scene cosine sobol" "$scene nee pcg") ;;
  esac
done
material_cases+=("background nee pcg" "background mis sobol")
for case in "${material_cases[@]}"; do
  read -r scene integrator sampler <<<"$case"
  size=(--width 24 --height 16)
  [ "$scene" = showcase ] && size=(--width 32 --height 24)
  args=(render "${size[@]}" --spp 4 --moments --integrator "$integrator" --seed 7)
  [ "$integrator" = workshop ] || args+=(--sampler "$sampler")
  same_images_scene_args "$scene" "$work"
  render_both "material-$scene-$integrator-$sampler.exr" "${args[@]}"
done
# Path guiding (--guiding): training and the guided render, on the box and the showcase.
for integrator in nee mis; do
  render_both "guided-builtin-$integrator.exr" render --width 24 --height 16 --spp 8 \
    --guiding --guide-training-spp 4 --integrator "$integrator" --seed 3
done
render_both "guided-showcase-mis.exr" render --width 32 --height 24 --spp 4 --guiding \
  --guide-training-spp 4 --integrator mis --seed 7 "${SAME_IMAGES_SHOWCASE:-$top/scenes/materials.gltf}"
echo "$compared images compared bit for bit in $work: $((compared - differ)) identical, $differ different"
[ "$differ" -eq 0 ]
