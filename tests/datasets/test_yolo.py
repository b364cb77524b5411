"""Ultralytics YOLO on an exported data set (test-only extra, AGPL, in its own process): `yolo train` for one
epoch at imgsz 320 on a 50-image export completes from scratch on the CPU; the experiment's confusion matrix."""

from __future__ import annotations

import importlib.util
import os

import numpy as np
import pytest
from PIL import Image

from usvsim.datasets import DatasetSpec, generate
from usvsim.datasets.labels import DETECTABLE
from usvsim.experiments.detection_robustness import confusion, run_yolo

HAVE_YOLO = bool(os.environ.get("USVSIM_YOLO_PYTHON")) or importlib.util.find_spec("ultralytics") is not None


@pytest.mark.skipif(not HAVE_YOLO, reason="needs USVSIM_YOLO_PYTHON or ultralytics (extra: yolo)")
def test_yolo_trains_one_epoch_on_a_50_image_export(tmp_path):
    root = generate(DatasetSpec("buoy_field", 50, tmp_path / "set", ("yolo",), 5, "clear_calm", (320, 240), (0.8, 0.2, 0.0)))
    assert len(list((root / "images").rglob("*.png"))) == 50
    job = {"train": str(root / "data.yaml"), "epochs": 1, "imgsz": 320, "evals": {"clear": str(root / "data.yaml")}}
    result = run_yolo(job, tmp_path / "yolo")
    assert (tmp_path / "yolo" / "train" / "weights" / "last.pt").exists()
    assert 0.0 <= result["evals"]["clear"]["map50"] <= 1.0 and result["evals"]["clear"]["predictions"]


def test_confusion_matrix_matches_by_iou(tmp_path):
    (tmp_path / "labels" / "val").mkdir(parents=True)
    (tmp_path / "images" / "val").mkdir(parents=True)
    Image.new("RGB", (100, 100)).save(tmp_path / "images" / "val" / "a.png")
    red, green = DETECTABLE.index("buoy_red"), DETECTABLE.index("buoy_green")
    (tmp_path / "labels" / "val" / "a.txt").write_text(f"{red} 0.2 0.2 0.2 0.2\n{green} 0.7 0.7 0.2 0.2\n")
    preds = {"a.png": [[red, 0.9, 11.0, 11.0, 30.0, 30.0], [red, 0.8, 61.0, 60.0, 80.0, 80.0], [red, 0.7, 0, 80, 10, 90]]}
    m = confusion(tmp_path, preds)
    n = len(DETECTABLE)
    assert m[red, red] == 1 and m[green, red] == 1 and m[n, red] == 1 and m.sum() == 3
    assert np.count_nonzero(m) == 3


def test_coco_map50_by_pycocotools(tmp_path):
    from usvsim.datasets.labels import CLASSES
    from usvsim.experiments.detection_robustness import coco_map50

    red, green = DETECTABLE.index("buoy_red"), DETECTABLE.index("buoy_green")
    anns = [{"id": i + 1, "image_id": 1, "category_id": CLASSES.index(DETECTABLE[c]), "bbox": box, "area": 400,
             "iscrowd": 0} for i, (c, box) in enumerate([(red, [10, 10, 20, 20]), (green, [60, 60, 20, 20])])]  # fmt: skip
    cats = [{"id": CLASSES.index(c), "name": c} for c in DETECTABLE]
    (tmp_path / "annotations").mkdir()
    coco = {"images": [{"id": 1, "file_name": "val/a.png", "width": 100, "height": 100}], "annotations": anns, "categories": cats}
    (tmp_path / "annotations" / "val.json").write_text(__import__("json").dumps(coco))
    hit = [red, 0.9, 10.0, 10.0, 30.0, 30.0]
    assert coco_map50(tmp_path, {"a.png": [hit, [green, 0.8, 60.0, 60.0, 80.0, 80.0]]})["map50"] == pytest.approx(1.0)
    half = coco_map50(tmp_path, {"a.png": [hit, [green, 0.8, 0.0, 60.0, 20.0, 80.0]]})  # the green box missed
    assert half["per_class"] == {"buoy_red": pytest.approx(1.0), "buoy_green": 0.0} and half["map50"] == pytest.approx(0.5)


_READ_SEGMENTS = """
import json, sys
from ultralytics.data import YOLODataset
import yaml
data = yaml.safe_load(open(sys.argv[1]))
data["channels"] = 3
ds = YOLODataset(img_path=sys.argv[2], data=data, task="segment", imgsz=320, augment=False)
print(json.dumps([{"file": l["im_file"], "cls": l["cls"].ravel().tolist(),
                   "segments": [s.tolist() for s in l["segments"]]} for l in ds.labels]))
"""


@pytest.mark.skipif(not HAVE_YOLO, reason="needs USVSIM_YOLO_PYTHON or ultralytics (extra: yolo)")
def test_ultralytics_reads_the_segment_labels(tmp_path):
    """`--yolo-labels segment`: Ultralytics' own dataset loader (task segment) takes every line (none corrupt), with
    the classes and polygon points as written."""
    import json
    import subprocess
    import sys

    root = generate(DatasetSpec("buoy_field", 3, tmp_path / "set", ("yolo",), 5, "clear_calm", (320, 240), (1.0, 0.0, 0.0),
                                yolo_labels="segment"))  # fmt: skip
    python = os.environ.get("USVSIM_YOLO_PYTHON") or sys.executable
    out = subprocess.run([python, "-c", _READ_SEGMENTS, str(root / "data.yaml"), str(root / "images" / "train")],
                         capture_output=True, text=True, check=True, cwd=tmp_path)  # fmt: skip
    labels = json.loads(out.stdout.strip().splitlines()[-1])
    assert len(labels) == 3 and sum(len(x["cls"]) for x in labels) > 10
    for read in labels:
        stem = os.path.splitext(os.path.basename(read["file"]))[0]
        lines = (root / "labels" / "train" / f"{stem}.txt").read_text().split("\n")
        written = [[float(v) for v in line.split()] for line in lines if line]
        assert read["cls"] == [w[0] for w in written]
        for points, w in zip(read["segments"], written):
            np.testing.assert_allclose(np.ravel(points), w[1:], atol=1e-6)
