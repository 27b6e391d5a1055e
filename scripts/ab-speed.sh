#!/usr/bin/env bash
# Speed of two vkpath binaries on the same machine in one run, for "speed within the noise"
# checks of a change: renders the built-in Cornell box, the material showcase
# (scenes/materials.gltf) and the generated scale-test scene of 10^6 triangles with `mis`, alternating old and new ROUNDS times (so that a load
# change on a shared machine hits both alike), and prints each one's median render seconds
# (the kernel's time, without setup) and the ratio new / old.
# Usage: scripts/ab-speed.sh OLD_VKPATH NEW_VKPATH [ROUNDS]
set -euo pipefail
old=$(realpath "$1")
new=$(realpath "$2")
rounds=${3:-3}
top=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scenes=("cornell::--width 256 --height 256 --spp 64" "materials:$top/scenes/materials.gltf:--width 128 --height 96 --spp 16"
  "million::--generated 1000000 --width 128 --height 128 --spp 16")
for entry in "${scenes[@]}"; do
  IFS=: read -r name scene args <<<"$entry"
  for round in $(seq "$rounds"); do
    for side in old new; do
      binary=$old; [ $side = new ] && binary=$new
      # shellcheck disable=SC2086
      "$binary" render $scene $args --integrator mis --seed 1 --quiet --json -o "$work/$side.exr" \
        >"$work/$name-$side-$round.json"
    done
  done
done
python3 - "$work" "$rounds" <<'PY'
import json, statistics, sys
work, rounds = sys.argv[1], int(sys.argv[2])
for name in ("cornell", "materials", "million"):
    medians = {}
    for side in ("old", "new"):
        seconds = [json.load(open(f"{work}/{name}-{side}-{r}.json"))["render_seconds"] for r in range(1, rounds + 1)]
        medians[side] = statistics.median(seconds)
        print(f"{name:9} {side}: " + " ".join(f"{s:.3f}" for s in seconds) + f"  median {medians[side]:.3f} s")
    print(f"{name:9} new/old: {medians['new'] / medians['old']:.3f}")
PY
