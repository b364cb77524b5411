"""Writes a data set: images, mask PNGs, COCO JSON, Ultralytics YOLO labels and data.yaml, per-frame metadata.

Layout under the output folder (`<split>`: train, val, test; `<stem>`: frame number and camera):
  images/<split>/<stem>.png              RGB
  labels/<split>/<stem>.txt              YOLO: `class cx cy w h` per object, normalized to 0–1 (visible box), or
                                         `class x1 y1 x2 y2 ...` (its polygon, `YOLO_LABELS`: segment)
  masks/instance/<split>/<stem>.png      uint16: object index + 1 (0: none); ids as in the COCO file
  masks/semantic/<split>/<stem>.png      uint8: class id (classes.json)
  annotations/<split>.json               COCO: bbox = visible box, segmentation = RLE (uncompressed, or
                                         compressed) or polygons (`COCO_SEGMENTATIONS`), all exact,
                                         plus amodal_bbox, visible_fraction, truncated, object name,
                                         fog_transmittance (datasets/fog_sight.py)
  meta/<stem>.json                       everything needed to re-render the frame (look, poses, qpos, time)
  data.yaml, classes.json, dataset.json  YOLO data file, class table (ids, LaRS groups), the run's settings
All files are written with sorted keys and fixed precision, so the same seed gives the same bytes.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
from pathlib import Path, PurePosixPath

import numpy as np
from PIL import Image

from usvsim.core.errors import UsvsimError
from usvsim.datasets.labels import CLASSES, DETECTABLE, GROUPS, ObjectLabel

FORMATS = ("yolo", "coco", "masks")
COCO_SEGMENTATIONS = ("rle", "compressed_rle", "polygon")  # how COCO `segmentation` is written; see coco_segmentation
YOLO_LABELS = ("box", "segment")  # what a YOLO label line holds: the visible box, or the polygon (Ultralytics' segment)
SPLITS = ("train", "val", "test")


FOLDERS = ("images", "labels", "masks", "meta", "annotations")  # what a set writes under its folder, with
TOP_FILES = ("data.yaml", "classes.json", "dataset.json")  # these
_STEM = r"\d{6,}(?:_[A-Za-z0-9_.-]+)?"  # frame number, then the camera's name when the scenario has several
_SPLIT = "(?:" + "|".join(SPLITS) + ")"
_OURS = re.compile(  # every name a set writes; `.<name>.partial`: a file being written (write_atomic)
    "|".join((rf"images/{_SPLIT}/{_STEM}\.png", rf"labels/{_SPLIT}/{_STEM}\.txt",
              rf"masks/(?:instance|semantic)/{_SPLIT}/{_STEM}\.png", rf"meta/{_STEM}\.json",
              rf"annotations/{_SPLIT}\.json", *(re.escape(n) for n in TOP_FILES)))  # fmt: skip
)


def written_by_usvsim(rel: str) -> bool:
    """Whether the path `rel` (relative to a set's folder, '/'-separated) is one a data set writes."""
    path = PurePosixPath(rel)
    if path.name.startswith(".") and path.name.endswith(".partial"):
        path = path.with_name(path.name[1 : -len(".partial")])
    return _OURS.fullmatch(str(path)) is not None


def set_files(out: Path) -> tuple[list[str], list[str]]:
    """(files a data set writes, other files and links) under `out`'s data set folders and top files, relative
    to `out`, sorted. Links are never followed, and count as other files."""
    ours, other = [], []
    for name in (*FOLDERS, *TOP_FILES):
        path = out / name
        if path.is_symlink() or (path.exists() and path.is_dir() != (name in FOLDERS)):
            other.append(name)
        elif path.is_file():
            ours.append(name)
        elif path.is_dir():
            for folder, dirs, files in os.walk(path):
                base = Path(folder).relative_to(out).as_posix()
                for entry in sorted(files) + [d for d in sorted(dirs) if os.path.islink(os.path.join(folder, d))]:
                    rel = f"{base}/{entry}"
                    (ours if written_by_usvsim(rel) and not os.path.islink(out / rel) else other).append(rel)
    return sorted(ours), sorted(other)


def remove_set(out: Path, files: list[str]) -> None:
    """Removes a data set's `files` (relative to `out`, as set_files gives them), then its folders left empty."""
    folders = set()
    for rel in files:
        try:
            (out / rel).unlink()
        except OSError as exc:
            raise UsvsimError(f"cannot remove {out / rel} of the previous data set: {exc.strerror or exc}") from None
        folders.update(p for p in PurePosixPath(rel).parents if str(p) != ".")
    for folder in sorted(folders, key=lambda p: -len(p.parts)):
        try:
            (out / folder).rmdir()
        except OSError:  # not empty: something not ours stays, and its folder
            pass


class WriteError(UsvsimError):
    """A file of the set could not be written (a full disk, permissions): one line naming it."""


def write_atomic(path: Path, data: bytes) -> None:
    """Writes `data` to `path` through `.<name>.partial` in the same folder, renamed when complete: a full disk
    left truncated PNGs under their real names (a ~100-line traceback besides). On an error the partial file is
    removed and a WriteError names the path."""
    partial = path.with_name(f".{path.name}.partial")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(partial, "wb") as f:
            f.write(data)
        os.replace(partial, path)
    except OSError as exc:
        with contextlib.suppress(OSError):
            partial.unlink()
        raise WriteError(f"cannot write {path}: {exc.strerror or exc}") from None


def dump_json(path: Path, data) -> None:
    write_atomic(path, (json.dumps(data, sort_keys=True, separators=(",", ":")) + "\n").encode())


def write_png(path: Path, array: np.ndarray) -> None:
    """PNG, fast: RGB by OpenCV with the "up" filter and Huffman-only deflate (noisy images barely compress;
    2x faster than zlib level 1, files ~10 % smaller than Pillow's), masks by Pillow at level 1."""
    if array.ndim == 3:
        import cv2

        ok, data = cv2.imencode(".png", array[:, :, ::-1], _rgb_png_params())
        if not ok:
            raise WriteError(f"{path}: OpenCV could not encode the image as PNG")
        write_atomic(path, data.tobytes())
    else:
        buffer = io.BytesIO()
        Image.fromarray(array).save(buffer, format="PNG", compress_level=1)
        write_atomic(path, buffer.getvalue())


def _rgb_png_params() -> list[int]:
    import cv2

    return [cv2.IMWRITE_PNG_COMPRESSION, 1, cv2.IMWRITE_PNG_STRATEGY, cv2.IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY,
            cv2.IMWRITE_PNG_FILTER, cv2.IMWRITE_PNG_FILTER_UP]  # fmt: skip


def rle(flat: np.ndarray, shape, start: int = 0) -> dict:
    """COCO uncompressed RLE of a boolean mask of `shape` (H, W) given in column-major order (`mask.T.ravel()`):
    run lengths, starting with 0s. `flat` may be the slice [start, start + len) of the whole mask when the
    mask is 0 outside it (the columns of the object's box)."""
    change = np.flatnonzero(flat[1:] != flat[:-1]) + 1
    edges = np.concatenate([[0], change, [flat.size]])
    counts = np.diff(edges).tolist()
    if flat[0]:
        counts = [0, *counts]
    counts[0] += start
    tail = int(shape[0]) * int(shape[1]) - start - flat.size
    if tail and flat[-1]:
        counts.append(tail)  # a new run of 0s
    elif tail:
        counts[-1] += tail  # the last run is 0s
    return {"size": [int(shape[0]), int(shape[1])], "counts": counts}


def rle_string(counts: list[int]) -> str:
    """COCO's compressed RLE `counts` string of run lengths (pycocotools' rleToString: each count, minus the one
    two before it from the third on, in 5-bit groups with a continuation bit, offset by 48)."""
    out = []
    for i, count in enumerate(counts):
        x, more = count - counts[i - 2] if i > 2 else count, True
        while more:
            c = x & 0x1F
            x >>= 5
            more = x != -1 if c & 0x10 else x != 0
            out.append(chr((c | 0x20 if more else c) + 48))
    return "".join(out)


def polygons(mask: np.ndarray, x0: int, y0: int) -> list[list[float]]:
    """COCO polygons (pixel-edge coordinates, [x1, y1, x2, y2, ...]) of a boolean mask whose top-left pixel is
    (x0, y0): one polygon per connected part, its holes joined to its outline by a bridge walked there and back
    (COCO polygons have no holes; the bridge adds nothing under an even-odd fill). The outlines run through the
    centres of the pixels of the mask drawn at twice the resolution, a quarter pixel inside the edges:
    pycocotools draws exactly the mask back from them (tests/datasets/test_dataset.py)."""
    import cv2

    big = np.pad(np.repeat(np.repeat(mask.astype(np.uint8), 2, axis=0), 2, axis=1), 1)
    contours, hierarchy = cv2.findContours(big, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
    rings = [(c.reshape(-1, 2) - 0.5) / 2.0 + (x0, y0) for c in contours]  # the padding's pixel, then half pixels
    out: list[list[float]] = []
    links: list[list[int]] = [[int(v) for v in row] for row in np.asarray(hierarchy).reshape(-1, 4)] if (
        hierarchy is not None) else []  # per ring: next, previous, first child, parent  # fmt: skip
    for i, (_, _, child, parent) in enumerate(links):
        if parent >= 0:
            continue
        path, start = [rings[i], rings[i][:1]], rings[i][:1]
        while child >= 0:
            path += [rings[child], rings[child][:1], start]
            child = links[child][0]
        out.append([round(float(v), 2) for v in np.concatenate(path).ravel()])
    return out


def coco_segmentation(kind: str, instance: np.ndarray, lab: ObjectLabel, shape) -> dict | list:
    """An object's COCO `segmentation`: `rle` (uncompressed counts, exact), `compressed_rle` (pycocotools'
    string form, exact, smaller) or `polygon` (exact through pycocotools; what Detectron2's default polygon
    masks and Ultralytics' COCO converter read). Computed over the object's box only."""
    x0, y0, x1, y1 = (int(v) for v in lab.visible_box)
    if kind == "polygon":
        return polygons(instance[y0:y1, x0:x1] == lab.instance, x0, y0)
    counts = rle(instance[:, x0:x1].T.ravel() == lab.instance, shape, x0 * shape[0])
    return counts if kind == "rle" else {**counts, "counts": rle_string(counts["counts"])}


def yolo_polygon(mask: np.ndarray, x0: int, y0: int) -> np.ndarray:
    """An object's Ultralytics segment polygon (N, 2) in pixel-edge coordinates: polygons()' parts (holes already
    bridged) in one ring, each part joined at its vertex nearest to the ring so far by a bridge walked there and
    back, which adds nothing under an even-odd fill (Ultralytics' COCO converter also joins an object's parts into
    one line, at their nearest points); nearest, because rasterizers that draw the edges (OpenCV's fillPoly, which
    Ultralytics uses) paint a bridge's pixels. At least 4 points: every part is at least a pixel's square."""
    parts = [np.asarray(p, float).reshape(-1, 2) for p in polygons(mask, x0, y0)]
    path = parts[0]
    for part in parts[1:]:  # both closed walks: the last point is the first
        d = np.linalg.norm(path[:, None, :] - part[None, :-1, :], axis=2)
        i, j = np.unravel_index(int(np.argmin(d)), d.shape)
        ring = np.concatenate([part[j:-1], part[: j + 1]])  # the part, from vertex j back to it
        path = np.concatenate([path[: i + 1], ring, path[i:]])
    return path


def yolo_line(kind: str, instance: np.ndarray, lab: ObjectLabel, shape) -> str:
    """An object's YOLO label line: `class cx cy w h` (`box`: the visible box) or `class x1 y1 ... xn yn`
    (`segment`: yolo_polygon), normalized by the image's width and height to [0, 1]."""
    h, w = shape[:2]
    x0, y0, x1, y1 = lab.visible_box
    cls = DETECTABLE.index(lab.category)
    if kind == "box":
        return f"{cls} {(x0 + x1) / 2 / w:.6f} {(y0 + y1) / 2 / h:.6f} {(x1 - x0) / w:.6f} {(y1 - y0) / h:.6f}"
    ix0, iy0, ix1, iy1 = (int(v) for v in lab.visible_box)
    ring = yolo_polygon(instance[iy0:iy1, ix0:ix1] == lab.instance, ix0, iy0) / (w, h)
    return f"{cls} " + " ".join(f"{v:.6f}" for v in ring.ravel())


def _round(box) -> list[float]:
    return [round(float(v), 3) for v in box]


class DatasetWriter:
    def __init__(self, out: Path, formats: tuple[str, ...], segmentation: str = "rle", yolo_labels: str = "box"):
        self.out, self.formats, self.segmentation, self.yolo_labels = Path(out), formats, segmentation, yolo_labels
        self.coco: dict[str, dict] = {s: {"images": [], "annotations": []} for s in SPLITS}
        self.next_ann = 1

    def frame(
        self, split: str, stem: str, image_id: int, rgb, instance, semantic, labels: list[ObjectLabel], meta
    ):
        """Writes one frame's files (thread-safe)."""
        write_png(self.out / "images" / split / f"{stem}.png", rgb)
        if "masks" in self.formats:
            write_png(self.out / "masks" / "instance" / split / f"{stem}.png", instance)
            write_png(self.out / "masks" / "semantic" / split / f"{stem}.png", semantic)
        if "yolo" in self.formats:
            lines = [yolo_line(self.yolo_labels, instance, lab, rgb.shape) for lab in labels]
            write_atomic(self.out / "labels" / split / f"{stem}.txt", "".join(line + "\n" for line in lines).encode())
        dump_json(self.out / "meta" / f"{stem}.json", meta)

    def coco_records(self, split: str, stem: str, image_id: int, shape, instance, labels: list[ObjectLabel]):
        """COCO image record and annotations of one frame, without annotation ids (thread-safe; hand them to
        add_coco in frame order). Each segmentation is computed over the object's box only."""
        if "coco" not in self.formats:
            return None
        image = {"id": image_id, "file_name": f"{split}/{stem}.png", "height": shape[0], "width": shape[1]}
        anns = []
        for lab in labels:
            x0, y0, x1, y1 = lab.visible_box
            ax0, ay0, ax1, ay1 = lab.amodal_box
            anns.append({
                "image_id": image_id, "category_id": CLASSES.index(lab.category),
                "bbox": _round([x0, y0, x1 - x0, y1 - y0]), "area": lab.visible_pixels, "iscrowd": 0,
                "segmentation": coco_segmentation(self.segmentation, instance, lab, shape), "amodal_bbox": _round([ax0, ay0, ax1 - ax0, ay1 - ay0]),
                "visible_fraction": round(lab.visible_fraction, 4), "truncated": lab.truncated, "object": lab.name,
                "instance": lab.instance, "fog_transmittance": round(lab.fog_transmittance, 4)})  # fmt: skip
        return split, image, anns

    def add_coco(self, records) -> None:
        """Adds coco_records' output (call in frame order: annotation ids count up)."""
        if records is None:
            return
        split, image, anns = records
        self.coco[split]["images"].append(image)
        for ann in anns:
            self.coco[split]["annotations"].append({"id": self.next_ann, **ann})
            self.next_ann += 1

    def finish(self, settings: dict) -> None:
        """The per-split COCO files, YOLO data.yaml, classes.json and dataset.json."""
        categories = [{"id": CLASSES.index(c), "name": c, "supercategory": GROUPS[c]} for c in DETECTABLE]
        if "coco" in self.formats:
            for split, coco in self.coco.items():
                info = {"description": "usvsim synthetic data set", "version": "1"}
                dump_json(
                    self.out / "annotations" / f"{split}.json",
                    {**coco, "categories": categories, "info": info},
                )
        if "yolo" in self.formats:
            for split in SPLITS:  # Ultralytics needs `train` and `val` in data.yaml and the val folder to exist
                for folder in ("images", "labels"):  # a split that got no frame: an empty folder
                    try:
                        (self.out / folder / split).mkdir(parents=True, exist_ok=True)
                    except OSError as exc:
                        raise WriteError(f"cannot create {self.out / folder / split}: {exc.strerror or exc}") from None
            names = "".join(f"  {i}: {c}\n" for i, c in enumerate(DETECTABLE))
            task = ("# labels: segment polygons (class x1 y1 x2 y2 ...): train a segmentation model (yolov8n-seg.yaml, "
                    "task=segment)\n" if self.yolo_labels == "segment" else "")  # Ultralytics' -seg data files
            # have the detection ones' keys; the model names the task
            write_atomic(self.out / "data.yaml", f"{task}path: {self.out.resolve()}\ntrain: images/train\n"
                                                 f"val: images/val\ntest: images/test\nnames:\n{names}".encode())  # fmt: skip
        dump_json(
            self.out / "classes.json",
            [{"id": i, "name": c, "group": GROUPS[c]} for i, c in enumerate(CLASSES)],
        )
        dump_json(self.out / "dataset.json", settings)
