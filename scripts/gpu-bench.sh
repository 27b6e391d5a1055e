#!/usr/bin/env bash
# vkpath on a GPU in one short call: the devices, then `vkpath bench` (samples/s and rays/s per
# integrator) on the Cornell box at 1920x1080 and on a generated 10^6-triangle scene, then cold
# against warm start-up. Every step has its own time limit, so the whole script ends within
# 7 minutes (typically far less), whatever hangs.
#
# On the device machine (see /work/.library/device/README.md): build here with
# `cargo build --release`, copy the binary to .gpu/vkpath (ignored by git: `echo /.gpu/ >>
# .git/info/exclude`), download the loader debs into .gl once (the README's apt-get line), then
#   run(command="bash scripts/gpu-bench.sh", carry=[".gl", ".gpu"], timeout_s=480)
# The results (JSON and a log) go to $OUT when it is set (the device tool brings them back),
# else to ./gpu-bench-out.
#
# Here, on lavapipe, `bash scripts/gpu-bench.sh --small target/release/vkpath` runs the same steps
# at tiny sizes without --require-gpu (a check of the script, not a measurement).
set -uo pipefail

small=0
if [ "${1:-}" = "--small" ]; then
    small=1
    shift
fi
bin=${1:-.gpu/vkpath}
out=${OUT:-gpu-bench-out}
mkdir -p "$out"
log="$out/gpu-bench.log"
: >"$log"
say() { echo "$@" | tee -a "$log"; }

# The Vulkan loader, when the machine has none (the device README's recipe).
if ! ldconfig -p | grep 'libvulkan\.so\.1' >/dev/null; then
    if ls .gl/*.deb >/dev/null 2>&1; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    else
        say "no Vulkan loader on this machine and no .gl/*.deb to unpack"
        exit 1
    fi
fi
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$icd" ]; then
    export VK_DRIVER_FILES=$icd
fi
if [ ! -x "$bin" ]; then
    say "no vkpath binary at '$bin' (build it with cargo build --release and carry it)"
    exit 1
fi

if [ $small = 1 ]; then
    gpu=()
    cornell=(--width 64 --height 36 --spp 8 --reference-spp 64)
    generated=(--generated 20000 --width 64 --height 36 --spp 4 --reference-spp 16 --repeats 1)
    startup=(--width 64 --height 36)
else
    gpu=(--require-gpu)
    # 2.07 M pixels: 64 spp is 133 M samples per integrator, the reference 1024 spp 2.1 G.
    cornell=(--width 1920 --height 1080 --spp 64 --reference-spp 1024)
    generated=(--generated 1000000 --width 1920 --height 1080 --spp 16 --reference-spp 256 --repeats 2)
    startup=(--width 1920 --height 1080)
fi

# Runs a step under a time limit, into the log and to a file of its own.
step() {
    local name=$1 limit=$2
    shift 2
    say "== $name (limit ${limit} s): $*"
    local started=$SECONDS
    timeout --kill-after=10 "$limit" "$@" >"$out/$name.out" 2>>"$log"
    local status=$?
    cat "$out/$name.out" | tee -a "$log"
    say "== $name: exit $status after $((SECONDS - started)) s"
}

step devices 30 "$bin" devices
step devices-json 30 "$bin" devices --json
if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,memory.total --format=csv | tee -a "$log"
fi
# Each bench prints its table (samples/s, rays/s, relMSE, efficiency per integrator) and the
# same as JSON.
step cornell 90 "$bin" bench "${gpu[@]}" "${cornell[@]}" --repeats 3
# --repeats once: clap refuses an option given twice (this step failed with exit 2 when
# the array held --repeats too).
step cornell-json 60 "$bin" bench "${gpu[@]}" "${cornell[@]}" --repeats 1 --json
step generated 150 "$bin" bench "${gpu[@]}" "${generated[@]}" --json
# Cold start (empty pipeline and driver caches) against warm, in one run.
step startup 60 "$bin" bench "${gpu[@]}" --startup "${startup[@]}"
say "done in $SECONDS s; results in $out"
