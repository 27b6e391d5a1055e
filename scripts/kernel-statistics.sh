#!/usr/bin/env bash
# A GPU compiler's view of the path tracer's kernels without a GPU: builds them with Mesa 25's
# RADV on its null device (an AMD RDNA3 GPU that RADV_FORCE_FAMILY makes up; no command
# buffer ever runs) and prints, per integrator, what RADV_DEBUG=shaderstats reports:
# registers (VGPRs), subgroups per SIMD (occupancy: fewer registers, more subgroups to hide
# memory latency), spills, static instructions, and ACO's latency and inverse-throughput
# estimates. Static figures: a loop counts once per unrolled copy, whatever it runs.
# Usage: scripts/kernel-statistics.sh [--traversal constant|bvh|compressed-bvh] [SCENE.gltf] [INTEGRATOR...]
#        (default: the built-in Cornell box, constant triangles, cosine nee mis)
# Builds the release example kernel_statistics (examples/kernel_statistics.rs) first.
# The Mesa 25 packages come from scripts/mesa25.sh (bookworm-backports, unpacked privately).
set -euo pipefail
cd "$(dirname "$0")/.."
lvp_icd=$(bash scripts/mesa25.sh)
root=$(cd "$(dirname "$lvp_icd")/../../../.." && pwd)
radeon="$root/usr/lib/x86_64-linux-gnu/libvulkan_radeon.so"
[ -f "$radeon" ] || { echo "kernel-statistics: no $radeon in the Mesa 25 packages" >&2; exit 2; }
icd=$(mktemp --suffix=.json)
cache=$(mktemp -d)
trap 'rm -rf "$icd" "$cache"' EXIT
printf '{"ICD":{"api_version":"1.4.305","library_path":"%s"},"file_format_version":"1.0.0"}\n' "$radeon" > "$icd"
args=("$@")
has_integrator=false
for a in "${args[@]}"; do
  case "$a" in workshop|direct-illumination|cosine|nee|mis) has_integrator=true ;; esac
done
$has_integrator || args+=(cosine nee mis)
example=target/release/examples/kernel_statistics
# (the kernels are embedded in it: build it from the tree as it is)
cargo build --quiet --release --example kernel_statistics
# The null device's teardown crashes inside RADV after everything was printed: keep the output.
output=$(MESA_SHADER_CACHE_DISABLE=true RADV_DEBUG=shaderstats RADV_FORCE_FAMILY=navi31 VK_DRIVER_FILES="$icd" \
  VKPATH_CACHE_DIR="$cache" "$example" "${args[@]}" 2>&1 || true)
grep -q '^kernel:' <<<"$output" || { echo "$output" >&2; echo "kernel-statistics: no kernel was built" >&2; exit 1; }
echo "| kernel | build | VGPRs | subgroups/SIMD | spilled VGPRs | instructions | latency | inverse throughput |"
echo "|---|---|---|---|---|---|---|---|"
awk '
  /^kernel:/ { name=$2; build=$3; next }
  /^VGPRs:/ { vgprs=$2 }
  /^Spilled VGPRs:/ { spilled=$3 }
  /^Subgroups per SIMD:/ { subgroups=$4 }
  /^Instructions:/ { instructions=$2 }
  /^Latency:/ { latency=$2 }
  /^Inverse Throughput:/ { printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", name, build, vgprs, subgroups, spilled, instructions, latency, $3 }
' <<<"$output"
