#!/usr/bin/env bash
# Proves that a change which moves the random numbers of the importance-sampled integrators
# (fixed sample dimensions, glsl/sample_dimensions.glsl) changes their images only
# statistically, and keeps Sobol's stratification. OLD is a vkpath built from the commit
# before the change, NEW one built from it. docs/sampling.md records a run.
# Usage: scripts/sample-dimensions-proof.sh OLD_VKPATH NEW_VKPATH [WORK_DIR]
#
# 1. Agreement: every scene of scripts/same-images-scenes.sh (the scenes of
#    scripts/same-images.sh) with cosine, nee and mis and both samplers, plus the guided
#    renders of scripts/same-images.sh (nee and mis on the box, mis on the showcase), both
#    samplers: OLD and NEW each render it (PROOF_SIZE^2 pixels, PROOF_SPP spp, --moments,
#    different seeds so that the two are independent), and NEW's `vkpath compare` tests NEW's
#    image against OLD's with the variances of both (8x8 blocks). The family-wise level is 0.01
#    over all the comparisons of the run (Šidák: each image at 1 - 0.99^(1/N)). For Sobol the
#    moments' variance (iid samples) overstates the error of the mean, so those tests are
#    conservative; part 2 judges Sobol against a reference as well.
# 2. Stratification: mis with Sobol on the Cornell box, the showcase and the environment scene:
#    the relMSE (`vkpath compare`'s, mean of (A - R)^2 / (R^2 + 0.01)) of PROOF_SEEDS renders at
#    PROOF_SPP spp against a reference of PROOF_REFERENCE_SPP spp (OLD, PCG: independent of
#    both), averaged over the seeds, OLD against NEW. NEW / OLD must lie within 5 %; the line
#    prints the ratio's standard error from the seed-to-seed spread, and the reference's own
#    relMSE (what it adds to both), estimated as part 1's PCG render of the scene (mis, OLD)
#    measured against it, times PROOF_SPP / PROOF_REFERENCE_SPP.
# Small images, few samples; one render at a time (the machine is shared). Exit 0 if every
# comparison agrees and every ratio is within 5 %.
set -euo pipefail
old=$(realpath "$1")
new=$(realpath "$2")
work=${3:-$(mktemp -d)}
top=$(cd "$(dirname "$0")/.." && pwd)
size=${PROOF_SIZE:-64}
spp=${PROOF_SPP:-64}
seeds=${PROOF_SEEDS:-8}
reference_spp=${PROOF_REFERENCE_SPP:-4096}
mkdir -p "$work/agree" "$work/strata"
# shellcheck source=same-images-scenes.sh
source "$top/scripts/same-images-scenes.sh"
same_images_make_scenes "$old" "$work"

# Part 1: the cases, as "scene integrator sampler guided".
cases=()
for scene in "${SAME_IMAGES_SCENES[@]}"; do
  for integrator in cosine nee mis; do
    for sampler in pcg sobol; do
      cases+=("$scene $integrator $sampler no")
    done
  done
done
for sampler in pcg sobol; do
  cases+=("builtin nee $sampler yes" "builtin mis $sampler yes" "showcase mis $sampler yes")
done
alpha=$(python3 -c "print(1 - 0.99 ** (1 / ${#cases[@]}))")
echo "part 1: ${#cases[@]} comparisons, ${size}x${size}, $spp spp, each at alpha $alpha (family-wise 0.01)"
failed=0
for case in "${cases[@]}"; do
  read -r scene integrator sampler guided <<<"$case"
  name="$scene-$integrator-$sampler"
  args=(render --width "$size" --height "$size" --spp "$spp" --moments --integrator "$integrator" --sampler "$sampler")
  if [ "$guided" = yes ]; then
    args+=(--guiding --guide-training-spp 4)
    name="guided-$name"
  fi
  same_images_scene_args "$scene" "$work"
  rm -f "$work/agree/$name-old.exr" "$work/agree/$name-new.exr"
  "$old" "${args[@]}" --seed 11 -o "$work/agree/$name-old.exr" >"$work/agree/$name-old.log" 2>&1 || true
  "$new" "${args[@]}" --seed 12 -o "$work/agree/$name-new.exr" >"$work/agree/$name-new.log" 2>&1 || true
  if report=$("$new" compare --json --quiet --alpha "$alpha" "$work/agree/$name-new.exr" "$work/agree/$name-old.exr" 2>&1); then
    verdict=agree
  else
    verdict=DIFFER
    failed=$((failed + 1))
  fi
  python3 - "$name" "$verdict" "$report" <<'PY'
import json, sys
name, verdict, text = sys.argv[1:4]
try:
    r = json.loads(text)
    w = r["worst"]
    print(f"{verdict:6} {name:32} worst z {w['z']:+6.2f} p {w['p_value']:.2e}  relMSE new vs old {r['relative_mse']:.3e}")
except (ValueError, KeyError, TypeError):
    print(f"{verdict:6} {name:32} {text.strip()[:200]}")
PY
done

# Part 2: relMSE against a reference, OLD against NEW.
strata_failed=0
echo "part 2: mis, sobol, ${size}x${size}, $spp spp x $seeds seeds against a $reference_spp spp PCG reference"
for scene in builtin showcase environment; do
  args=(render --width "$size" --height "$size" --integrator mis)
  same_images_scene_args "$scene" "$work"
  reference="$work/strata/$scene-reference.exr"
  [ -f "$reference" ] || "$old" "${args[@]}" --sampler pcg --spp "$reference_spp" --seed 1000 -o "$reference" >/dev/null 2>&1
  values=()
  for side in old new; do
    binary=$old; [ $side = new ] && binary=$new
    for seed in $(seq 1 "$seeds"); do
      image="$work/strata/$scene-$side-$seed.exr"
      "$binary" "${args[@]}" --sampler sobol --spp "$spp" --seed "$seed" -o "$image" >/dev/null 2>&1
      # (compare exits 1 where it finds the render inconsistent with the reference; only
      # the relMSE of its report is read here)
      values+=("$side:$({ "$new" compare --json --quiet "$image" "$reference" || true; } | python3 -c 'import json,sys; print(json.load(sys.stdin)["relative_mse"])')")
    done
  done
  reference_self=$({ "$new" compare --json --quiet "$work/agree/$scene-mis-pcg-old.exr" "$reference" || true; } | python3 -c "import json,sys; print(json.load(sys.stdin)['relative_mse'] * $spp / $reference_spp)")
  if ! python3 - "$scene" "$reference_self" "${values[@]}" <<'PY'
import math, sys
scene, reference_self = sys.argv[1], float(sys.argv[2])
sides = {"old": [], "new": []}
for item in sys.argv[3:]:
    side, value = item.split(":")
    sides[side].append(float(value))
def mean_and_error(xs):
    m = sum(xs) / len(xs)
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else float("nan")
    return m, s / math.sqrt(len(xs))
(old_mean, old_error), (new_mean, new_error) = mean_and_error(sides["old"]), mean_and_error(sides["new"])
ratio = new_mean / old_mean
ratio_error = ratio * math.sqrt((old_error / old_mean) ** 2 + (new_error / new_mean) ** 2)
ok = abs(ratio - 1) <= 0.05
print(f"{'within' if ok else 'OUTSIDE':7} {scene:12} relMSE old {old_mean:.4e} +- {old_error:.1e}, new {new_mean:.4e} +- {new_error:.1e}, "
      f"new/old {ratio:.4f} +- {ratio_error:.4f}; reference's own relMSE {reference_self:.2e} ({100 * reference_self / old_mean:.1f} % of old's)")
sys.exit(0 if ok else 1)
PY
  then
    strata_failed=$((strata_failed + 1))
  fi
done
echo "part 1: $((${#cases[@]} - failed)) of ${#cases[@]} agree; part 2: $((3 - strata_failed)) of 3 within 5 % ($work)"
[ "$failed" -eq 0 ] && [ "$strata_failed" -eq 0 ]
