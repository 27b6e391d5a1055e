#!/usr/bin/env bash
# The light tree against the power CDF on scenes/many_lights.gltf (1000 emissive triangles
# along a corridor, none in view; scripts/make_many_lights_scene.py), in one `vkpath bench`
# run: nee with --light-selection power and tree against the same high-spp reference (mis
# with the tree), efficiency 1 / (relMSE * seconds) of each, and their ratio.
# Usage: [WIDTH=64 HEIGHT=48 SPP=64 REFERENCE_SPP=4096] bash benches/light_tree.sh [VKPATH]
#        [extra vkpath bench options, e.g. --sampler sobol --repeats 1]
#   VKPATH defaults to target/release/vkpath (build it with `cargo build --release`);
#   e.g. WIDTH=32 HEIGHT=24 REFERENCE_SPP=1024 for a quick look.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$top/target/release/vkpath}
shift || true
scene="$top/scenes/many_lights.gltf"
json=$(mktemp)
"$bin" bench "$scene" --integrators nee --light-selections power,tree --light-selection tree \
    --width "${WIDTH:-64}" --height "${HEIGHT:-48}" --spp "${SPP:-64}" \
    --reference-spp "${REFERENCE_SPP:-4096}" "$@" --json >"$json"
python3 - "$json" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
print(f"{report['device']} | {report['scene']} ({report['triangle_count']} triangles) | "
      f"{report['width']}x{report['height']} | {report['spp']} spp | reference {report['reference_spp']} spp (mis, tree)")
print(f"{'integrator':<12}{'selection':<10}{'render s':>10}{'relMSE':>11}{'efficiency':>12}")
by = {}
for r in report["results"]:
    by[r["light_selection"]] = r
    print(f"{r['integrator']:<12}{r['light_selection']:<10}{r['render_seconds']:>10.3f}"
          f"{r['relative_mse']:>11.5f}{r['efficiency']:>12.2f}")
print(f"tree / power efficiency: {by['tree']['efficiency'] / by['power']['efficiency']:.2f}x")
PY
rm -f "$json"
