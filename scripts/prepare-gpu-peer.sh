#!/usr/bin/env bash
# Prepares, on this machine (no GPU needed), everything scripts/gpu-peer.sh needs on a lent GPU
# machine, in folders git ignores (.peer/ is in .gitignore, .gl/ too). Idempotent: each step is
# skipped when its output is already there (--force redoes them).
#
#   1. pip download --no-deps the cp312 manylinux wheels of mitsuba 3.9.1 and drjit 1.5.0
#      (the device has Python 3.12 and numpy, no Mitsuba) into .peer/wheels/ (64.4 MiB).
#   2. One zip of both packages, without the variant modules a GPU run does not use
#      (mitsuba/llvm_*, scalar_spectral*, cuda_ad_mono*, cuda_ad_spectral*; the C++ headers and
#      CMake files under mitsuba/include and mitsuba/cmake, which nothing imports) ->
#      .peer/carry/mitsuba-drjit-cp312.zip. It keeps cuda_ad_rgb, scalar_rgb, libmitsuba,
#      libembree3 (libmitsuba.so needs it even on CUDA), the plugins and data.
#   3. cargo build --release (nice), then the binary stripped and xz-compressed ->
#      .peer/carry/vkpath.xz (the device script unpacks it to .peer/bin/vkpath there).
#   4. The Vulkan loader debs into .gl/ (the device README's recipe).
#   5. Prints what each device call carries and its total against the 64 MiB limit (the
#      tracked files travel too).
#   6. Optionally (--check-trim): the same trim applied to the cp311 wheels for this machine's
#      Python, imported from the zip and rendered with scalar_rgb: a check that the trimmed
#      package still imports and renders (the cp312 zip itself cannot be imported here).
#
# Then, on a machine with a lent GPU, the one call that scripts/gpu-peer.sh's top describes.
set -euo pipefail
cd "$(dirname "$0")/.."
force=0
check_trim=0
for a in "$@"; do
    case $a in
        --force) force=1 ;;
        --check-trim) check_trim=1 ;;
        *) echo "usage: $0 [--force] [--check-trim]" >&2; exit 2 ;;
    esac
done
grep -qx '/.peer/' .gitignore || { echo "/.peer/ is not in .gitignore" >&2; exit 1; }
grep -qx '/.gl/' .gitignore || grep -qx '/.gl/' "$(git rev-parse --git-common-dir)/info/exclude" ||
    { echo "/.gl/ is ignored by neither .gitignore nor info/exclude" >&2; exit 1; }
mkdir -p .peer/wheels .peer/carry

# 1. Wheels.
platforms=(--platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64
           --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64)
if [ $force = 1 ] || ! ls .peer/wheels/mitsuba-3.9.1-cp312-*.whl .peer/wheels/drjit-1.5.0-cp312-*.whl >/dev/null 2>&1; then
    echo "[1] pip download mitsuba 3.9.1 + drjit 1.5.0 (cp312)"
    python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
        "${platforms[@]}" -d .peer/wheels mitsuba==3.9.1 drjit==1.5.0
else
    echo "[1] wheels already in .peer/wheels"
fi

# 2. The trimmed zip (the trim rule is in trim_zip, used for the check in step 6 too).
trim_zip() {  # trim_zip OUT.zip WHEEL...
    python3 - "$@" <<'EOF'
import re, sys, zipfile
out, wheels = sys.argv[1], sys.argv[2:]
drop = re.compile(r"^mitsuba/(llvm_|scalar_spectral|cuda_ad_mono|cuda_ad_spectral)[^/]*"
                  r"|^mitsuba/(include|cmake)/|\.dist-info/")
kept = dropped = 0
with zipfile.ZipFile(out + ".tmp", "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
    for wheel in wheels:
        with zipfile.ZipFile(wheel) as w:
            for info in w.infolist():
                if drop.search(info.filename):
                    dropped += info.file_size
                    continue
                kept += info.file_size
                z.writestr(info, w.read(info.filename), compress_type=zipfile.ZIP_DEFLATED, compresslevel=9)
import os
os.replace(out + ".tmp", out)
print(f"    kept {kept / 2**20:.1f} MiB unpacked, dropped {dropped / 2**20:.1f} MiB; zip {os.path.getsize(out) / 2**20:.1f} MiB")
EOF
}
zip=.peer/carry/mitsuba-drjit-cp312.zip
if [ $force = 1 ] || [ ! -f $zip ]; then
    echo "[2] trimmed zip -> $zip"
    trim_zip $zip .peer/wheels/mitsuba-3.9.1-cp312-*.whl .peer/wheels/drjit-1.5.0-cp312-*.whl
else
    echo "[2] $zip already built"
fi
python3 - $zip <<'EOF'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
need = ["mitsuba/cuda_ad_rgb.", "mitsuba/scalar_rgb.", "mitsuba/libmitsuba.so", "mitsuba/libembree3.so",
        "mitsuba/plugins/path.so", "mitsuba/plugins/ply.so", "mitsuba/plugins/ldsampler.so", "drjit/__init__.py"]
missing = [n for n in need if not any(x.startswith(n) for x in names)]
bad = [x for x in names if x.startswith(("mitsuba/llvm_", "mitsuba/cuda_ad_mono", "mitsuba/cuda_ad_spectral"))]
if missing or bad:
    sys.exit(f"    zip check FAILED: missing {missing}, unwanted {bad[:3]}")
print(f"    zip check: {len(names)} files, cuda_ad_rgb and its plugins present, no llvm/mono/spectral variants")
EOF

# 3. The binary.
if [ $force = 1 ] || [ ! -f .peer/carry/vkpath.xz ] || [ target/release/vkpath -nt .peer/carry/vkpath.xz ]; then
    echo "[3] cargo build --release; strip; xz"
    nice cargo build --release 2>&1 | tail -1
    strip -o .peer/vkpath.stripped target/release/vkpath
    xz -9 -T1 -c .peer/vkpath.stripped >.peer/carry/vkpath.xz.tmp && mv .peer/carry/vkpath.xz.tmp .peer/carry/vkpath.xz
    rm -f .peer/vkpath.stripped
    git rev-parse HEAD >.peer/carry/vkpath.commit
else
    echo "[3] .peer/carry/vkpath.xz is newer than target/release/vkpath"
fi

# 4. Loader debs (the device README's recipe).
if [ $force = 1 ] || ! ls .gl/libvulkan1_*.deb >/dev/null 2>&1; then
    echo "[4] loader debs -> .gl/"
    mkdir -p .gl /tmp/amd64/partial
    o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
    apt-get "${o[@]}" update >/dev/null
    (cd .gl && apt-get "${o[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null)
else
    echo "[4] loader debs already in .gl/"
fi

# 5. Sizes.
mib() { du -cb "$@" | tail -1 | awk '{printf "%.1f", $1 / 1048576}'; }
tracked=$(git ls-files -z | xargs -0 du -cb 2>/dev/null | tail -1 | awk '{printf "%.1f", $1 / 1048576}')
untracked=$(git ls-files -z --others --exclude-standard | xargs -0 -r du -cb 2>/dev/null | tail -1 | awk '{printf "%.1f", $1 / 1048576}')
carry=$(mib .peer/carry .gl)
total=$(awk -v a="$tracked" -v b="${untracked:-0}" -v c="$carry" 'BEGIN { printf "%.1f", a + b + c }')
echo "[5] one call carries .peer/carry ($(mib .peer/carry) MiB: zip $(mib $zip), vkpath.xz $(mib .peer/carry/vkpath.xz)) and .gl ($(mib .gl) MiB)"
echo "    + tracked files $tracked MiB + untracked, not ignored ${untracked:-0} MiB = $total MiB of 64 MiB"
if awk -v t="$total" 'BEGIN { exit !(t <= 63.0) }'; then
    echo "    fits ONE call: run(command=\"bash scripts/gpu-peer.sh\", carry=[\".gl\", \".peer/carry\"], timeout_s=570)"
else
    echo "    does NOT fit one call: split on one warm machine (see scripts/gpu-peer.sh's top):"
    echo "      run(command=\"bash scripts/gpu-peer.sh --unpack-only\", carry=[\".peer/carry\"], timeout_s=120)"
    echo "      run(command=\"bash scripts/gpu-peer.sh\", carry=[\".gl\"], timeout_s=540)"
fi

# 6. Optional: the trim rule checked on this machine's Python (3.11), scalar_rgb.
if [ $check_trim = 1 ]; then
    echo "[6] trim check with the cp311 wheels (scalar_rgb render from the trimmed zip)"
    mkdir -p .peer/wheels311 .peer/trimcheck
    ls .peer/wheels311/mitsuba-3.9.1-cp311-*.whl >/dev/null 2>&1 ||
        python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.11 --implementation cp \
            "${platforms[@]}" -d .peer/wheels311 mitsuba==3.9.1 drjit==1.5.0
    trim_zip .peer/trimcheck/trim311.zip .peer/wheels311/*.whl
    rm -rf .peer/trimcheck/site && python3 -m zipfile -e .peer/trimcheck/trim311.zip .peer/trimcheck/site
    PYTHONPATH=$PWD/.peer/trimcheck/site python3 -c '
import drjit as dr, mitsuba as mi
print("    mitsuba imports from the trimmed zip; its config lists (modules may be absent):", len(mi.variants()), "variants")
mi.set_variant("scalar_rgb")
img = mi.render(mi.load_dict(mi.cornell_box()), spp=4)
print("    scalar_rgb render from the trimmed package:", img.shape, "mean", float(dr.mean(dr.ravel(img) if hasattr(dr, "ravel") else img.array)))'
fi
