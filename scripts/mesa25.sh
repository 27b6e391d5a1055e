#!/usr/bin/env bash
# Fetches Mesa 25's lavapipe (Debian 12's bookworm-backports, mesa-vulkan-drivers 25.x),
# whose Vulkan driver offers VK_KHR_ray_query, into a folder of its own WITHOUT installing it:
# the system's Mesa (22.3, no ray queries) stays the driver of everything else. Prints the
# path of the unpacked driver's ICD file on stdout; give it to a process through
# VK_DRIVER_FILES to run that process on Mesa 25 (scripts/test.sh exports it as
# VKPATH_RAY_QUERY_ICD for tests/ray_query_cli.rs). Idempotent: a second run reuses the
# folder. Needs root for apt-get (adding the suite and `apt-get update`) where the .deb is not
# cached yet.
#
#   bash scripts/mesa25.sh [FOLDER]     (default: target/mesa25)
set -euo pipefail
cd "$(dirname "$0")/.."
folder=$(realpath -m "${1:-target/mesa25}")
root="$folder/root"
icd="$root/usr/share/vulkan/icd.d/lvp_icd.json"
library="$root/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so"
if [ -f "$icd" ] && [ -f "$library" ] && grep -q "\"$library\"" "$icd"; then
  echo "$icd"
  exit 0
fi
mkdir -p "$folder"
deb=$(ls "$folder"/mesa-vulkan-drivers_25.*_amd64.deb 2>/dev/null | head -n 1 || true)
if [ -z "$deb" ]; then
  # The suite, with the same mirror as the machine's own bookworm entry (deb822 or one-line).
  if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    uri=$(awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
    if [ -z "$uri" ]; then
      uri=$(awk '$1 == "deb" && $3 == "bookworm" {print $2; exit}' /etc/apt/sources.list 2>/dev/null || true)
    fi
    uri=${uri:-http://deb.debian.org/debian}
    echo "adding bookworm-backports ($uri) to /etc/apt/sources.list.d/vkpath-backports.list" >&2
    echo "deb $uri bookworm-backports main" >/etc/apt/sources.list.d/vkpath-backports.list
  fi
  apt-get update -qq >&2
  # As root, apt-get download warns that it cannot drop privileges to _apt for the
  # download: harmless.
  (cd "$folder" && apt-get download -qq -t bookworm-backports mesa-vulkan-drivers >&2)
  deb=$(ls "$folder"/mesa-vulkan-drivers_*_amd64.deb | head -n 1)
  case "$(basename "$deb")" in
    mesa-vulkan-drivers_25.*) ;;
    *)
      echo "bookworm-backports gave $(basename "$deb"), not Mesa 25" >&2
      exit 1
      ;;
  esac
fi
rm -rf "$root"
dpkg -x "$deb" "$root"
# The ICD names its library by a bare file name (for the system's library path): point it
# at the unpacked one.
sed -i "s|\"library_path\": *\"[^\"]*\"|\"library_path\": \"$library\"|" "$icd"
grep -q "\"$library\"" "$icd" || {
  echo "cannot point $icd at $library" >&2
  exit 1
}
echo "$icd"
