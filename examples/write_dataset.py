#!/usr/bin/env python3
"""Write a tiny synthetic dataset from an animated glTF file (issue 56): per frame the
colour as PNG and EXR, the instance mask and the forward and backward optical flow as numpy
files, and one plain-JSON annotation file with each visible object's pixels and box and the
frame's camera (K and camera-to-world, OpenCV axes). With `pycocotools` installed each
object also gets its mask as COCO run-length encoding (`segmentation`), else none.

    pip install ./python
    python3 examples/write_dataset.py tests/data/BoxAnimated.gltf --frames 0..4 --out dataset

Layout of the output folder:
    image_0000.png, image_0000.exr   colour (sRGB PNG, linear EXR)
    mask_0000.npy                    (H, W) uint32 instance_id, 0 where nothing is hit
    flow_forward_0000.npy            (H, W, 2) float32 (du, dv) in pixels to frame + 1
    flow_backward_0000.npy           (H, W, 2) float32 to frame - 1 (x right, y down)
    annotations.json                 frames, objects (id, pixels, bbox [x0, y0, x1, y1]), cameras
"""

import argparse
import json
from pathlib import Path

import numpy as np

import vkpath

try:  # COCO's run-length encoding, from the well-kept library where it is installed
    from pycocotools import mask as coco_mask
except ImportError:
    coco_mask = None


def objects_of(mask: np.ndarray) -> list:
    """Each instance visible in `mask`: its ID, pixel count and box (x1, y1 excluded)."""
    objects = []
    for instance in np.unique(mask):
        if instance == 0:
            continue
        rows, columns = np.nonzero(mask == instance)
        entry = {
            "instance_id": int(instance),
            "pixels": int(rows.size),
            "bbox": [int(columns.min()), int(rows.min()), int(columns.max()) + 1, int(rows.max()) + 1],
        }
        if coco_mask is not None:
            rle = coco_mask.encode(np.asfortranarray((mask == instance).astype(np.uint8)))
            entry["segmentation"] = {"size": rle["size"], "counts": rle["counts"].decode("ascii")}
        objects.append(entry)
    return objects


def write_dataset(scene: str, frames: str, out: Path, fps: float = 24.0, size: int = 64, spp: int = 4) -> dict:
    """Renders `frames` of `scene` with their ground truth into `out`; returns the annotations."""
    out.mkdir(parents=True, exist_ok=True)
    annotations = {"scene": scene, "fps": fps, "frames": []}
    outputs = vkpath.render_frames(
        scene, frames=frames, fps=fps, width=size, height=size, spp=spp,
        background=(1.0, 1.0, 1.0),  # a white sky, for files without lights
        aovs=["instance_id", "motion"],
    )
    for frame, layers in outputs:
        name = f"{frame:04d}"
        vkpath.save(layers["image"], out / f"image_{name}.png")
        vkpath.save(layers["image"], out / f"image_{name}.exr")
        np.save(out / f"mask_{name}.npy", layers["instance_id"])
        np.save(out / f"flow_forward_{name}.npy", layers["motion_forward"][..., :2])
        np.save(out / f"flow_backward_{name}.npy", layers["motion_backward"][..., :2])
        camera = layers["camera"]
        annotations["frames"].append({
            "frame": frame,
            "time": frame / fps,
            "image": f"image_{name}.png",
            "objects": objects_of(layers["instance_id"]),
            "camera": {
                "k": camera["k"].tolist(),
                "camera_to_world_opencv": camera["camera_to_world_opencv"].tolist(),
                "width": camera["width"],
                "height": camera["height"],
            },
        })
    (out / "annotations.json").write_text(json.dumps(annotations, indent=1))
    return annotations


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="an animated .gltf/.glb file")
    parser.add_argument("--frames", default="0..4", help="START..END (END excluded)")
    parser.add_argument("--fps", type=float, default=24.0)
    parser.add_argument("--size", type=int, default=64, help="width and height in pixels")
    parser.add_argument("--spp", type=int, default=4)
    parser.add_argument("--out", type=Path, default=Path("dataset"))
    args = parser.parse_args()
    annotations = write_dataset(args.scene, args.frames, args.out, args.fps, args.size, args.spp)
    print(f"{len(annotations['frames'])} frames written to {args.out}")


if __name__ == "__main__":
    main()
