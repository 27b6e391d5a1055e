#!/usr/bin/env python3
"""Render with Ray: frames of a sequence, or sample-range shards of one still, as Ray tasks.

Each task runs the `vkpath` command line on the node Ray placed it on, with `num_gpus` GPUs
reserved for it (`--gpus-per-task`, default 1). Ray hands a task its GPU through
`CUDA_VISIBLE_DEVICES` (CUDA indices); the task's environment adds
`CUDA_DEVICE_ORDER=PCI_BUS_ID`, so that vkpath maps the index to the right Vulkan device (see
docs/distributed.md, "GPUs"). With `--gpus-per-task 0` (a machine without GPUs, e.g. lavapipe)
tasks reserve one CPU each instead, and vkpath takes the CPU device.

    # a local Ray (started by this script) rendering frames 0..7 of a glTF animation
    python3 examples/ray_render.py frames scene.gltf --frames 0..8 --out-dir frames
    # one still as 8 shards, merged by the driver into still/image.exr and image.png
    python3 examples/ray_render.py still scene.gltf --shards 8 --spp 4096 --out-dir still
    # on a cluster: --address auto (or ray://HEAD:10001) with a shared --out-dir

Every task prints vkpath's `--json` object; the driver collects them and says what ran where.
"""

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import ray


def task_environment() -> dict:
    """The environment of a vkpath task: Ray's CUDA_VISIBLE_DEVICES read in PCI order."""
    return {**os.environ, "CUDA_DEVICE_ORDER": "PCI_BUS_ID"}


def run_vkpath(vkpath: str, args: list) -> dict:
    """Runs `vkpath render ... --json` and returns its last JSON object (with the node)."""
    done = subprocess.run(
        [vkpath, *args, "--json"],
        env=task_environment(),
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        raise RuntimeError(f"vkpath {' '.join(args)} failed: {done.stderr.strip()}")
    report = json.loads(done.stdout.strip().splitlines()[-1])
    report["node"] = ray.util.get_node_ip_address()
    report["cuda_visible_devices"] = os.environ.get("CUDA_VISIBLE_DEVICES")
    return report


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mode", choices=["frames", "still"])
    parser.add_argument("scene", nargs="?", help="scene file (default: the built-in Cornell box)")
    parser.add_argument("--frames", default="0..24", help="START..END (END excluded), frames mode")
    parser.add_argument("--fps", type=float, default=24)
    parser.add_argument("--shards", type=int, default=4, help="still mode: number of shards")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--out-dir", type=Path, required=True)
    parser.add_argument("--vkpath", default="vkpath", help="the vkpath binary on every node")
    parser.add_argument("--gpus-per-task", type=float, default=1)
    parser.add_argument("--address", default=None, help="Ray cluster (default: start a local one)")
    args = parser.parse_args()

    ray.init(address=args.address)
    if args.gpus_per_task > 0 and ray.cluster_resources().get("GPU", 0) < args.gpus_per_task:
        # Ray would queue the tasks forever, waiting for GPUs that never come.
        print("ray_render.py: the Ray cluster has no GPUs: use --gpus-per-task 0 (CPU devices)",
              file=sys.stderr)
        return 2
    out_dir = args.out_dir.resolve()
    out_dir.mkdir(parents=True, exist_ok=True)
    resources = (
        {"num_gpus": args.gpus_per_task} if args.gpus_per_task > 0 else {"num_cpus": 1}
    )
    render = ray.remote(**resources)(run_vkpath)
    common = [*([args.scene] if args.scene else []), "--spp", str(args.spp),
              "--width", str(args.width), "--height", str(args.height), "--quiet"]
    if args.mode == "frames":
        start, end = (int(x) for x in args.frames.split(".."))
        tasks = [
            render.remote(args.vkpath, ["render", *common, "--frames", f"{f}..{f + 1}",
                                        "--fps", str(args.fps), "--skip-existing",
                                        "-o", str(out_dir / "frame_####.png")])
            for f in range(start, end)
        ]
    else:
        tasks = [
            render.remote(args.vkpath, ["render", *common, "--shard", f"{i}/{args.shards}",
                                        "-o", str(out_dir / f"shard_{i}.exr")])
            for i in range(args.shards)
        ]
    reports = ray.get(tasks)
    for report in reports:
        print(json.dumps({key: report.get(key) for key in
                          ("outputs", "frame", "sample_range", "stop", "render_seconds",
                           "node", "cuda_visible_devices")}))
    if args.mode == "still":
        shards = [str(out_dir / f"shard_{i}.exr") for i in range(args.shards)]
        subprocess.run([args.vkpath, "merge", *shards, "-o", str(out_dir / "image.exr"),
                        "-o", str(out_dir / "image.png")], check=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
