"""`usvsim experiment detection-robustness`: the seed's clear-vs-foggy detection experiment (thesis §5.3, Fig. 32).

Two data sets of the `buoy_field` scenario: `clear_calm` (train + held-out val) and `foggy_wavy` (val only),
different seeds. A YOLOv8n is trained from scratch on the CPU on the clear training images (Ultralytics, an
AGPL test-only extra, run in its own process by experiments/yolo_job.py with the Python named by
USVSIM_YOLO_PYTHON, or this one if it has `ultralytics`), then evaluated on both held-out sets: mAP50 overall and per class
by pycocotools' COCOeval on the sets' COCO files (the independent evaluator; Ultralytics' own figure is kept
beside it), and a confusion matrix per set (rows: true class and background, columns: predicted with
confidence >= 0.25; matched one to one at IoU >= 0.5, normalized per true class), written as JSON and PNG.
The camera's field of view is halved (35°) so that the buoys are large enough for a detector trained from
scratch on a CPU budget; objects with fewer visible pixels than USVSIM_DR_MIN_PIXELS are not labelled.

Sizes come from the environment (defaults in brackets): USVSIM_DR_TRAIN [120] clear frames (80 % train),
USVSIM_DR_FOGGY [40], USVSIM_DR_EPOCHS [40], USVSIM_DR_IMGSZ [256], USVSIM_DR_MIN_PIXELS [40].
PASS: foggy mAP50 < clear mAP50.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from usvsim.core.errors import UsvsimError
from usvsim.datasets import DatasetSpec, generate
from usvsim.datasets.labels import CLASSES, DETECTABLE

JOB = Path(__file__).with_name("yolo_job.py")
CONFUSION_CONF = 0.25  # predictions counted in the confusion matrices; mAP uses all (confidence >= 0.001)
# From scratch on a CPU budget: no mosaic and little scaling (mosaic would halve the buoys), AdamW at a set
# learning rate (Ultralytics' automatic choice for 18 class names is 4.5e-4: too slow to leave the start),
# images cached in RAM.
TRAIN_ARGS = {"mosaic": 0.0, "scale": 0.2, "translate": 0.1, "cache": "ram", "warmup_epochs": 1.0,
              "optimizer": "AdamW", "lr0": 0.003}  # fmt: skip
FOV_DEG = 35.0  # the scenario camera's 70° halved: buoys twice as large in the image


def yolo_python() -> str:
    """The interpreter that runs the YOLO job: USVSIM_YOLO_PYTHON, else this one if it has ultralytics."""
    python = os.environ.get("USVSIM_YOLO_PYTHON")
    if python:
        found = shutil.which(python)  # a path or a name on PATH; checked before the data sets are made
        if found is None:
            raise UsvsimError(f"USVSIM_YOLO_PYTHON={python!r}: no such executable (a Python that has torch, "
                              "torchvision and ultralytics; docs/datasets.md)")  # fmt: skip
        probe = "import importlib.util, sys; sys.exit(importlib.util.find_spec('ultralytics') is None)"
        try:
            has = subprocess.run([found, "-c", probe], capture_output=True, timeout=120).returncode == 0
        except (OSError, subprocess.TimeoutExpired):
            has = False
        if not has:
            raise UsvsimError(f"USVSIM_YOLO_PYTHON={python!r}: cannot import ultralytics with it (it needs torch, "
                              "torchvision and ultralytics; docs/datasets.md)")  # fmt: skip
        return found
    if importlib.util.find_spec("ultralytics") is not None:
        return sys.executable
    raise UsvsimError("detection-robustness needs Ultralytics YOLO: set USVSIM_YOLO_PYTHON to a Python that has "
                      "torch, torchvision and ultralytics (docs/datasets.md)")  # fmt: skip


def run_yolo(job: dict, out: Path, python: str | None = None) -> dict:
    """Runs experiments/yolo_job.py on `job` in its own process; returns its yolo_result.json."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "job.json").write_text(json.dumps({**job, "out": str(out)}))
    env = dict(os.environ, YOLO_OFFLINE="1", YOLO_VERBOSE="false")
    proc = subprocess.run(
        [python or yolo_python(), str(JOB), str(out / "job.json")], capture_output=True, text=True, env=env
    )
    if proc.returncode != 0:
        raise UsvsimError(
            f"YOLO job failed: {proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else proc.returncode}"
        )
    return json.loads((out / "yolo_result.json").read_text())


def _iou(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """IoU matrix of boxes a (n, 4) and b (m, 4), x0 y0 x1 y1."""
    lo, hi = np.maximum(a[:, None, :2], b[None, :, :2]), np.minimum(a[:, None, 2:], b[None, :, 2:])
    inter = np.prod(np.clip(hi - lo, 0, None), axis=2)
    area = lambda x: np.prod(x[:, 2:] - x[:, :2], axis=1)  # noqa: E731
    return inter / (area(a)[:, None] + area(b)[None, :] - inter)


def confusion(root: Path, predictions: dict, n: int = len(DETECTABLE)) -> np.ndarray:
    """(n + 1)² counts: rows true class (last: background, i.e. false positives), columns predicted class
    (last: missed). Greedy one-to-one matching by IoU >= 0.5, most confident prediction first."""
    m = np.zeros((n + 1, n + 1), np.int64)
    for label in sorted((root / "labels" / "val").glob("*.txt")):
        from PIL import Image

        w, h = Image.open(root / "images" / "val" / f"{label.stem}.png").size
        rows = np.array(
            [[float(v) for v in line.split()] for line in label.read_text().splitlines()]
        ).reshape(-1, 5)
        truth = np.c_[
            rows[:, 1] - rows[:, 3] / 2,
            rows[:, 2] - rows[:, 4] / 2,
            rows[:, 1] + rows[:, 3] / 2,
            rows[:, 2] + rows[:, 4] / 2,
        ] * [w, h, w, h]
        preds = sorted(predictions.get(f"{label.stem}.png", []), key=lambda p: -p[1])
        used = np.zeros(len(truth), bool)
        for cls, _, *box in preds:
            iou = _iou(np.array([box]), truth)[0] if len(truth) else np.zeros(0)
            iou[used] = 0.0
            k = int(np.argmax(iou)) if len(iou) else -1
            if k >= 0 and iou[k] >= 0.5:
                used[k] = True
                m[int(rows[k, 0]), cls] += 1
            else:
                m[n, cls] += 1
        for k in np.flatnonzero(~used):
            m[int(rows[k, 0]), n] += 1
    return m


def _plot(matrices: dict, classes: list[str], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(matrices), figsize=(6 * len(matrices), 5.2))
    for ax, (name, mat) in zip(np.atleast_1d(axes), matrices.items()):
        im = ax.imshow(mat, vmin=0, vmax=1, cmap="Blues")
        ax.set_xticks(range(len(classes)), classes, rotation=60, ha="right", fontsize=7)
        ax.set_yticks(range(len(classes)), classes, fontsize=7)
        ax.set_xlabel("predicted")
        ax.set_ylabel("true")
        ax.set_title(f"{name}: normalized confusion")
        fig.colorbar(im, ax=ax, fraction=0.046)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def coco_map50(root: Path, predictions: dict) -> dict:
    """mAP50 (IoU 0.5, all areas) of the predictions on the held-out split by pycocotools' COCOeval, the
    independent evaluator: overall and per class present in the ground truth."""
    from pycocotools.coco import COCO
    from pycocotools.cocoeval import COCOeval

    gt = COCO(str(root / "annotations" / "val.json"))
    ids = {Path(im["file_name"]).name: im["id"] for im in gt.dataset["images"]}
    dets = [{"image_id": ids[name], "category_id": CLASSES.index(DETECTABLE[cls]), "score": score,
             "bbox": [x0, y0, x1 - x0, y1 - y0]}
            for name, preds in predictions.items() for cls, score, x0, y0, x1, y1 in preds]  # fmt: skip
    if not dets:
        return {"map50": 0.0, "per_class": {}}
    # typeshed's pycocotools stub types `resFile` as a path; COCO.loadRes also takes the result list itself
    ev = COCOeval(gt, gt.loadRes(dets), "bbox")  # pyright: ignore[reportArgumentType]
    ev.evaluate()
    ev.accumulate()
    precision = ev.eval["precision"][0, :, :, 0, -1]  # IoU 0.5, recall points, classes, all areas, 100 dets
    per_class = {}
    for k, cat in enumerate(ev.params.catIds):
        if gt.getAnnIds(catIds=[cat]):
            p = precision[:, k]
            per_class[gt.cats[cat]["name"]] = float(p[p > -1].mean()) if (p > -1).any() else 0.0
    return {"map50": float(np.mean(list(per_class.values()))), "per_class": per_class}


SIZES = {  # key: (environment variable, default, least value)
    "clear_frames": ("USVSIM_DR_TRAIN", 120, 2), "foggy_frames": ("USVSIM_DR_FOGGY", 40, 1),
    "epochs": ("USVSIM_DR_EPOCHS", 40, 1), "imgsz": ("USVSIM_DR_IMGSZ", 256, 32),
    "min_visible_pixels": ("USVSIM_DR_MIN_PIXELS", 40, 0)}  # fmt: skip


def _sizes() -> dict:
    """The run's sizes from the environment; a UsvsimError naming the variable for a value that is not a whole
    number at or above its least value (it was a ValueError traceback, or a data set error naming no variable)."""
    sizes = {}
    for key, (var, default, least) in SIZES.items():
        text = os.environ.get(var, str(default))
        try:
            sizes[key] = int(text)
        except ValueError:
            sizes[key] = least - 1
        if sizes[key] < least:
            raise UsvsimError(f"{var}={text!r}: must be a whole number >= {least}")
    return sizes


def run(out_dir: Path, progress: Callable[[str], None] | None = None) -> dict:
    """The experiment; `progress` (if given) hears one line as each stage starts."""
    say = progress or (lambda _text: None)
    sizes, python = _sizes(), yolo_python()  # both fail now, not after the data sets are made
    work, imgsz = Path(out_dir) / "detection_robustness_data", sizes["imgsz"]
    size, formats, min_px = (imgsz, imgsz * 3 // 4), ("yolo", "coco"), sizes["min_visible_pixels"]
    say(f"rendering {sizes['clear_frames']} clear and {sizes['foggy_frames']} foggy frames ...")
    clear = generate(DatasetSpec("buoy_field", sizes["clear_frames"], work / "clear", formats, 11, "clear_calm",
                                 size, (0.8, 0.2, 0.0), min_px, horizontal_fov_deg=FOV_DEG), force=True)  # fmt: skip
    foggy = generate(DatasetSpec("buoy_field", sizes["foggy_frames"], work / "foggy", formats, 12, "foggy_wavy",
                                 size, (0.0, 1.0, 0.0), min_px, horizontal_fov_deg=FOV_DEG), force=True)  # fmt: skip
    job = {"train": str(clear / "data.yaml"), "epochs": sizes["epochs"], "imgsz": imgsz, "batch": 8,
           "conf": 0.001, "train_args": TRAIN_ARGS,
           "evals": {"clear": str(clear / "data.yaml"), "foggy": str(foggy / "data.yaml")}}  # fmt: skip
    say(f"training YOLOv8n for {sizes['epochs']} epochs on the CPU and evaluating it (most of the run) ...")
    result = run_yolo(job, work / "yolo", python)
    present = sorted({int(line.split()[0]) for root in (clear, foggy) for f in (root / "labels").rglob("*.txt")
                      for line in f.read_text().splitlines()})  # fmt: skip
    keep = [*present, len(DETECTABLE)]
    classes = [DETECTABLE[i] for i in present] + ["background"]
    summary, matrices, counts = {}, {}, {}
    for name, root in (("clear", clear), ("foggy", foggy)):
        preds = result["evals"][name]["predictions"]
        confident = {k: [p for p in v if p[1] >= CONFUSION_CONF] for k, v in preds.items()}
        m = confusion(root, confident)[np.ix_(keep, keep)]
        counts[name] = m.tolist()
        matrices[name] = m / np.maximum(m.sum(axis=1, keepdims=True), 1)
        coco = coco_map50(root, preds)
        summary[f"{name}_map50"] = coco["map50"]
        summary[f"{name}_map50_per_class"] = coco["per_class"]
        summary[f"{name}_map50_ultralytics"] = result["evals"][name]["map50"]
    passed = summary["foggy_map50"] < summary["clear_map50"]
    out = {"passed": passed, "summary": summary, "classes": classes, "confusion_counts": counts,
           "confusion_normalized": {k: v.round(4).tolist() for k, v in matrices.items()}, "sizes": sizes,
           "train_args": TRAIN_ARGS, "confusion_min_confidence": CONFUSION_CONF}  # fmt: skip
    (Path(out_dir) / "detection_robustness.json").write_text(json.dumps(out, indent=1))
    _plot(matrices, classes, Path(out_dir) / "detection_robustness.png")
    return out
