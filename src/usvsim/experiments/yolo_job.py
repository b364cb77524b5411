"""Train and evaluate an Ultralytics YOLO detector from scratch on the CPU; run as a script by the Python that
has `ultralytics` (AGPL: a test-only extra, kept in its own process). Imports nothing from usvsim.

    python yolo_job.py JOB.json   # {"train": data.yaml, "evals": {name: data.yaml}, "epochs", "imgsz", "out"}
Writes <out>/yolo_result.json: per evaluation set mAP50 (all classes and per class) and predictions per
validation image (class, confidence, box x0 y0 x1 y1 in pixels; confidence >= job["conf"]) for the caller's own
confusion matrix and COCO evaluation. job["train_args"]: further Ultralytics training arguments.
"""

import json
import sys
from pathlib import Path


def main(job_path: str) -> None:
    from ultralytics import YOLO  # pyright: ignore[reportMissingImports] (in USVSIM_YOLO_PYTHON's venv only)

    job = json.loads(Path(job_path).read_text())
    out = Path(job["out"])
    model = YOLO(job.get("model", "yolov8n.yaml"))  # architecture only: random weights, nothing downloaded
    model.train(data=job["train"], epochs=job["epochs"], imgsz=job["imgsz"], device="cpu", workers=0,
                pretrained=False, amp=False, plots=False, project=str(out), name="train", exist_ok=True,
                seed=job.get("seed", 0), deterministic=True, verbose=False, batch=job.get("batch", 8),
                **job.get("train_args", {}))  # fmt: skip
    result = {"epochs": job["epochs"], "imgsz": job["imgsz"], "evals": {}}
    for name, data in job.get("evals", {}).items():
        metrics = model.val(data=data, split="val", imgsz=job["imgsz"], device="cpu", plots=False,
                            workers=0, verbose=False, project=str(out), name=f"val_{name}", exist_ok=True)  # fmt: skip
        per_class = {
            model.names[int(c)]: float(ap) for c, ap in zip(metrics.box.ap_class_index, metrics.box.ap50)
        }
        images = sorted((Path(data).parent / "images" / "val").glob("*.png"))
        preds = {}
        for r in model.predict(
            [str(p) for p in images], imgsz=job["imgsz"], device="cpu", conf=job.get("conf", 0.25), verbose=False,
            stream=True
        ):
            boxes = r.boxes
            preds[Path(r.path).name] = [[int(c), float(s), *map(float, b)]
                                        for c, s, b in zip(boxes.cls, boxes.conf, boxes.xyxy)]  # fmt: skip
        result["evals"][name] = {
            "map50": float(metrics.box.map50),
            "map50_per_class": per_class,
            "predictions": preds,
        }
    (out / "yolo_result.json").write_text(json.dumps(result, indent=1, sort_keys=True))


if __name__ == "__main__":
    main(sys.argv[1])
