"""`usvsim dataset`: COCO read back by pycocotools (masks, boxes, a loadRes/COCOeval round trip), YOLO layout,
masks, amodal boxes containing visible ones, byte-identical output for one seed, randomization errors."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import yaml
from PIL import Image
from typer.testing import CliRunner

from usvsim.cli.app import app
from usvsim.core.errors import UsvsimError
from usvsim.datasets.generate import DatasetSpec, generate
from usvsim.datasets.labels import CLASSES, DETECTABLE
from usvsim.datasets.randomization import load_randomization

FRAMES = 4


def _make(path, seed):
    spec = DatasetSpec("buoy_field", FRAMES, path, seed=seed, randomize="foggy_wavy", resolution=(320, 240),
                       splits=(0.5, 0.5, 0.0), min_visible_pixels=4)  # fmt: skip
    return generate(spec)


@pytest.fixture(scope="module")
def sets(tmp_path_factory):
    base = tmp_path_factory.mktemp("ds")
    return _make(base / "a", 7), _make(base / "b", 7), _make(base / "c", 8)


def _coco(root):
    from pycocotools.coco import COCO

    return {
        s: COCO(str(root / "annotations" / f"{s}.json"))
        for s in ("train", "val")
        if (root / "images" / s).exists()
    }


def test_coco_masks_boxes_and_eval_round_trip(sets):
    from pycocotools import mask as mask_utils
    from pycocotools.cocoeval import COCOeval

    root = sets[0]
    checked = 0
    for coco in _coco(root).values():
        for ann in coco.loadAnns(coco.getAnnIds()):
            rle = coco.annToRLE(ann)
            assert (
                np.abs(mask_utils.toBbox(rle) - np.array(ann["bbox"])).max() <= 1.0
            )  # mask bbox == visible box
            assert int(mask_utils.area(rle)) == ann["area"]
            x, y, w, h = ann["bbox"]
            ax, ay, aw, ah = ann["amodal_bbox"]
            assert ax <= x + 1e-6 and ay <= y + 1e-6 and x + w <= ax + aw + 1e-6 and y + h <= ay + ah + 1e-6
            info = coco.loadImgs(ann["image_id"])[0]
            inst = np.array(Image.open(root / "masks" / "instance" / info["file_name"]))
            assert np.array_equal(inst == ann["instance"], coco.annToMask(ann).astype(bool))
            checked += 1
        dets = [{"image_id": a["image_id"], "category_id": a["category_id"], "bbox": a["bbox"], "score": 1.0}
                for a in coco.loadAnns(coco.getAnnIds())]  # fmt: skip
        ev = COCOeval(coco, coco.loadRes(dets), "bbox")
        ev.evaluate(), ev.accumulate(), ev.summarize()
        assert ev.stats[1] == pytest.approx(1.0)  # AP50 of the ground truth against itself
    assert checked >= 4 * FRAMES // 2


def test_yolo_layout_and_semantic_masks(sets):
    root = sets[0]
    data = yaml.safe_load((root / "data.yaml").read_text())
    assert (
        data["train"] == "images/train" and data["val"] == "images/val" and data["names"][0] == DETECTABLE[0]
    )
    for label in (root / "labels").rglob("*.txt"):
        image = root / "images" / label.parent.name / f"{label.stem}.png"
        assert image.exists()
        for line in label.read_text().splitlines():
            cls, *box = line.split()
            assert 0 <= int(cls) < len(DETECTABLE) and all(0.0 <= float(v) <= 1.0 for v in box)
    sem = np.array(Image.open(next((root / "masks" / "semantic").rglob("*.png"))))
    assert {CLASSES.index("sky"), CLASSES.index("water")} <= set(np.unique(sem).tolist())
    meta = json.loads(next((root / "meta").glob("*.json")).read_text())
    assert (
        meta["look"]["fog"]["visibility_m"] is not None
        and len(meta["qpos"]) > 7
        and meta["scene"]["buoy_offset_m"]
    )


def test_same_seed_same_bytes_other_seed_differs(sets):
    a, b, c = sets
    files = sorted(
        p.relative_to(a) for p in a.rglob("*") if p.is_file() and p.name not in ("data.yaml", "dataset.json")
    )
    assert len(files) > 4 * FRAMES
    for rel in files:
        assert (a / rel).read_bytes() == (b / rel).read_bytes(), rel
    ma, mc = (json.loads((root / "meta" / "000000.json").read_text()) for root in (a, c))
    for path in load_randomization("foggy_wavy").look:
        section, key = path.split(".")
        if not isinstance(ma["look"][section][key], list):  # constants (the fog colour) stay
            assert ma["look"][section][key] != mc["look"][section][key], path
    for key in ("vessel_yaw_deg", "camera_height_m", "camera_pitch_deg", "buoy_offset_m"):
        assert ma["scene"][key] != mc["scene"][key]


def test_bad_randomization_and_cli_errors(tmp_path):
    bad = tmp_path / "r.yaml"
    bad.write_text("version: 1\nscene: {buoy_offset: {uniform: [0, 1]}}\n")
    with pytest.raises(UsvsimError, match="scene"):
        load_randomization(bad)
    bad.write_text("version: 1\nlook: {sun.azimut_deg: {uniform: [0, 1]}}\n")
    with pytest.raises(UsvsimError, match="azimut_deg"):
        generate(DatasetSpec("buoy_field", 1, tmp_path / "x", randomize=str(bad)))
    result = CliRunner().invoke(
        app, ["dataset", "buoy_field", "--out", str(tmp_path / "y"), "--randomize", "nope"]
    )
    assert result.exit_code == 2 and "no such file or preset" in result.output
    result = CliRunner().invoke(app, ["dataset", "buoy_field", "--out", str(tmp_path / "z"), "--renderer", "ogre"])
    assert result.exit_code == 2 and "--renderer: 'ogre' is not one of shader, mujoco" in result.output
    assert not (tmp_path / "z").exists()  # nothing written


def test_a_bad_draw_mid_run_keeps_the_frames_before_it(tmp_path):
    """A normal without clip on a bounded key (fog visibility > 0) draws a bad value some frames in: it was a
    pydantic traceback, with the frames written so far left without annotations, data.yaml or dataset.json.
    Now a UsvsimError naming the key and the value, and a complete set of the frames before it."""
    rnd = tmp_path / "r.yaml"
    rnd.write_text("version: 1\nper: frame\nlook: {fog.visibility_m: {normal: [100, 60]}}\n")
    out = tmp_path / "set"
    with pytest.raises(UsvsimError, match=r"look.fog.visibility_m: .*greater than 0, got -.*stopped at frame 6") as e:
        generate(DatasetSpec("buoy_field", 30, out, seed=4, randomize=str(rnd), resolution=(64, 48)))  # 7th draw < 0
    assert "\n" not in str(e.value)
    meta = json.loads((out / "dataset.json").read_text())
    assert (meta["frames"], meta["frames_requested"], meta["stopped"]) == (6, 30, "error")
    coco = [json.loads((out / "annotations" / f"{s}.json").read_text()) for s in ("train", "val", "test")]
    assert sum(len(c["images"]) for c in coco) == 6 == len(list((out / "images").rglob("*.png")))
    assert (out / "data.yaml").is_file()


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [  # before: a TypeError, numpy's 'expected non-negative integer', a pydantic Camera error, or taken silently
        ({"frames": 1.5}, "frames must be a whole number >= 1, got 1.5"),
        ({"seed": -1}, "seed must be a whole number >= 0, got -1"),
        ({"splits": (0.5, 0.5)}, r"splits must be three .* got \(0.5, 0.5\)"),  # was taken (no test split)
        ({"resolution": (64.5, 48)}, "--resolution 64.5x48"),
        ({"settle_s": math.nan}, "settle_s must be a finite number of seconds >= 0, got nan"),
        ({"frame_interval_s": -1.0}, "frame_interval_s must be .* got -1.0"),
    ],
)
def test_dataset_spec_names_a_bad_value(tmp_path, kwargs, words):
    with pytest.raises(UsvsimError, match=words):
        DatasetSpec(**({"scenario": "buoy_field", "frames": 1, "out": tmp_path / "x"} | kwargs))
    assert not (tmp_path / "x").exists()


def test_dataset_spec_takes_a_format_string_and_a_str_folder(tmp_path):
    """formats="yolo,coco" was read letter by letter ('unknown [',', 'c', 'l', ...]'); out as a str made
    generate() return a str (docs: a Path)."""
    spec = DatasetSpec("buoy_field", 1, str(tmp_path / "s"), formats="yolo,coco", seed=np.int64(2),
                       resolution=(64, 48))  # fmt: skip
    assert spec.formats == ("yolo", "coco") and spec.out == tmp_path / "s"
    root = generate(spec)
    assert root == tmp_path / "s" and (root / "annotations" / "train.json").is_file() and not (root / "masks").exists()


def test_docs_blocks_run(tmp_path, monkeypatch):
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "datasets.md").read_text()
    (randomization,) = re.findall(r"```yaml\n(.*?)```", text, flags=re.DOTALL)
    (tmp_path / "r.yaml").write_text(randomization)
    assert load_randomization(tmp_path / "r.yaml").frames_per_episode == 5
    (code,) = re.findall(r"```python\n(.*?)```", text, flags=re.DOTALL)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/datasets.md", "exec"), {})
    assert len(list((tmp_path / "demo_set" / "meta").glob("*.json"))) == 2


def test_force_never_removes_files_usvsim_did_not_write(tmp_path):
    """--force deleted every file under images/, labels/, masks/, meta/ and annotations/: a user's photos in a
    folder holding no data set (QA: images/holiday.jpg, images/train/cat.png, labels/my_labels.csv) were gone.
    Now such a folder is refused with one line naming a file, with or without --force, and nothing is removed;
    a real set with a user's file inside it likewise; a set alone is replaced, its files only."""
    out = tmp_path / "ds"
    mine = {"images/holiday.jpg": "photo", "images/train/cat.png": "p2", "labels/my_labels.csv": "notes",
            "README.txt": "n"}  # fmt: skip
    for rel, text in mine.items():
        (out / rel).parent.mkdir(parents=True, exist_ok=True)
        (out / rel).write_text(text)
    args = ["dataset", "buoy_field", "--frames", "2", "--resolution", "64x48", "--out", str(out)]
    for extra in ([], ["--force"]):
        result = CliRunner().invoke(app, args + extra)
        assert result.exit_code == 2, result.output
        lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and "images/holiday.jpg" in lines[0] and "did not write" in lines[0], lines
        assert {rel: (out / rel).read_text() for rel in mine} == mine
        assert not (out / "dataset.json").exists() and not (out / "meta").exists()
    for rel in ("images/holiday.jpg", "images/train/cat.png", "labels/my_labels.csv"):
        (out / rel).unlink()
    assert CliRunner().invoke(app, args).exit_code == 0  # empty folders left: a set is written
    (out / "masks" / "instance" / "train" / "mine.png").write_text("x")  # a user's file inside the set
    result = CliRunner().invoke(app, args + ["--force"])
    assert result.exit_code == 2 and "masks/instance/train/mine.png" in result.stderr
    assert len(list((out / "meta").glob("*.json"))) == 2  # the set is untouched
    (out / "masks" / "instance" / "train" / "mine.png").unlink()
    assert CliRunner().invoke(app, [*args[:3], "1", *args[4:], "--force"]).exit_code == 0
    assert len(list((out / "meta").glob("*.json"))) == 1 and (out / "README.txt").read_text() == "n"


def test_instance_masks_hold_only_annotated_ids(tmp_path):
    """Objects under --min-visible-pixels were left out of COCO, YOLO and meta but still painted in the instance
    mask (QA: frame 0 instance 12 with 14 px): every id in the mask now has an annotation and a meta entry, and
    the objects left out keep their class in the semantic mask."""
    root = generate(DatasetSpec("buoy_field", 2, tmp_path / "s", seed=1, randomize="clear_calm", resolution=(320, 240),
                                splits=(1.0, 0.0, 0.0), min_visible_pixels=60))  # fmt: skip
    coco = json.loads((root / "annotations" / "train.json").read_text())
    left_out = 0
    for image in coco["images"]:
        stem = image["file_name"].split("/")[1][:-4]
        inst = np.array(Image.open(root / "masks" / "instance" / "train" / f"{stem}.png"))
        sem = np.array(Image.open(root / "masks" / "semantic" / "train" / f"{stem}.png"))
        annotated = {a["instance"] for a in coco["annotations"] if a["image_id"] == image["id"]}
        meta = {o["instance"] for o in json.loads((root / "meta" / f"{stem}.json").read_text())["objects"]}
        assert annotated and set(np.unique(inst)) - {0} == annotated == meta
        left_out += int(((inst == 0) & (sem >= CLASSES.index("vessel"))).sum())
    assert left_out > 0  # objects with 1-59 visible pixels are in the frames, unlabelled


def _limit_file_size():
    import resource
    import signal

    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # write() then fails with EFBIG instead of killing the process
    resource.setrlimit(resource.RLIMIT_FSIZE, (100_000, 100_000))


def test_a_full_disk_is_one_line_and_leaves_no_truncated_file(tmp_path):
    """A full disk (QA: a 600 kB tmpfs) was a ~100-line traceback with exit 1, and a truncated PNG under its real
    name. Filled here with a file-size limit (a 640x480 RGB PNG is ~140 kB): one line naming the file and the
    error, exit 2, and no file under a set's name that is not complete (nor a `.partial` one left)."""
    import subprocess
    import sys

    out = tmp_path / "set"
    cmd = [sys.executable, "-m", "usvsim", "dataset", "buoy_field", "--frames", "2", "--out", str(out)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600, preexec_fn=_limit_file_size)
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert proc.returncode == 2 and len(lines) == 1, proc.stderr[-3000:]
    assert "cannot write" in lines[0] and "File too large" in lines[0] and "000000.png" in lines[0], lines
    assert not (out / "dataset.json").exists() and not list(out.rglob("*.partial"))
    for png in out.rglob("*.png"):
        Image.open(png).load()  # complete
    assert "run again with --force" in lines[0]  # what is left is the set's own files: --force replaces them
    result = CliRunner().invoke(app, cmd[3:] + ["--force", "--resolution", "64x48"])
    assert result.exit_code == 0 and (out / "dataset.json").is_file(), result.output


def test_min_visible_fraction_help_names_the_mask_ratio():
    """The help said '(box areas)' while the filter reads the mask-based visible_fraction."""
    result = CliRunner().invoke(app, ["dataset", "--help"], env={"COLUMNS": "200", "TERM": "dumb"})
    text = " ".join(result.output.split())
    assert result.exit_code == 0 and "box areas" not in text
    assert "smaller visible_fraction (visible pixels / pixels of the object drawn alone" in text.replace("│ ", "")


def test_data_yaml_names_only_folders_that_exist(tmp_path):
    """data.yaml listed `val: images/val` and `test: images/test` when those splits got no frame, and Ultralytics
    refuses a data file whose val folder does not exist: the folders of a split without frames exist, empty."""
    root = generate(DatasetSpec("buoy_field", 1, tmp_path / "s", formats="yolo", resolution=(64, 48),
                                splits=(1.0, 0.0, 0.0)))  # fmt: skip
    data = yaml.safe_load((root / "data.yaml").read_text())
    for split in ("train", "val", "test"):
        assert (root / data[split]).is_dir() and (root / "labels" / split).is_dir()
    assert len(list((root / "images" / "train").iterdir())) == 1 and not list((root / "images" / "val").iterdir())


@pytest.mark.parametrize(
    ("scenario", "randomization", "words"),
    [
        ("buoy_field", "look: {sun.elevashun_deg: {uniform: [10, 60]}}", ["look.sun.elevashun_deg", "unknown key"]),
        ("buoy_field", "environment: {sea.type: sea_state, sea.code: 42}", ["environment", "sea"]),
        ("harbor", None, ["no camera sensor"]),
    ],
)
def test_scenario_and_look_errors_come_before_the_folder(tmp_path, scenario, randomization, words):
    """A bad look key, a bad drawn environment or a scenario without a camera were found only after --out was
    created: an empty folder was left, and a blank line printed before the error."""
    args = ["dataset", scenario, "--frames", "1", "--resolution", "64x48", "--out", str(tmp_path / "ds")]
    if randomization:
        (tmp_path / "r.yaml").write_text(f"version: 1\n{randomization}\n")
        args += ["--randomize", str(tmp_path / "r.yaml")]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2, result.output
    assert len(result.stderr.splitlines()) == 1 and result.stderr.startswith("usvsim: error:"), result.stderr
    for word in words:
        assert word in result.stderr
    assert not (tmp_path / "ds").exists()


def test_dataset_json_records_the_cameras_intrinsics(tmp_path):
    """dataset.json had `horizontal_fov_deg: null` and no intrinsics: now each camera's K, size and field of view,
    fx = (width / 2) / tan(hfov / 2) with the principal point at the image centre (pixel-centre coordinates)."""
    root = generate(DatasetSpec("buoy_field", 1, tmp_path / "s", resolution=(160, 120), formats="coco"))
    (cam,) = json.loads((root / "dataset.json").read_text())["cameras"]
    meta = json.loads((root / "meta" / "000000.json").read_text())
    fx = 80.0 / math.tan(math.radians(cam["horizontal_fov_deg"]) / 2)
    assert cam["camera"] == meta["camera"] and (cam["width"], cam["height"]) == (160, 120)
    assert 30.0 <= cam["horizontal_fov_deg"] <= 120.0 and cam["distortion"] == [0.0] * 5
    assert cam["fx"] == pytest.approx(fx, rel=1e-12) and cam["fy"] == pytest.approx(fx, rel=1e-12)
    assert (cam["cx"], cam["cy"]) == (79.5, 59.5)
    assert cam["K"] == [[cam["fx"], 0.0, 79.5], [0.0, cam["fy"], 59.5], [0.0, 0.0, 1.0]]


def test_without_randomize_a_note_says_every_frame_is_the_same(tmp_path):
    """Without --randomize every frame of buoy_field (a calm sea) is the same bytes, 0.5 s after a reset, and
    nothing said so: a one-line note on stderr after the run (docs/datasets.md). With --randomize, no note."""
    args = ["dataset", "buoy_field", "--frames", "2", "--resolution", "64x48", "--splits", "1,0,0"]
    result = CliRunner().invoke(app, [*args, "--out", str(tmp_path / "a")])
    assert result.exit_code == 0 and result.stdout.startswith("wrote 2 frames")
    (note,) = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert note.startswith("usvsim: note: no --randomize: nothing was drawn") and "0.5 s after a reset" in note
    images = sorted((tmp_path / "a" / "images" / "train").iterdir())
    assert len(images) == 2 and images[0].read_bytes() == images[1].read_bytes()
    result = CliRunner().invoke(app, [*args, "--out", str(tmp_path / "b"), "--randomize", "clear_calm"])
    assert result.exit_code == 0 and "note" not in result.stderr


def test_two_vessels_cameras_of_one_name_write_separate_files(tmp_path):
    """Two vessels each with a camera named `camera` wrote both frames to `000000_camera.png` (QA: the second
    overwrote the first, and the COCO file listed the same file_name twice with different labels): with a
    camera name shared between vessels every camera's files are `<frame>_<vessel>-<camera>`."""
    scenario = tmp_path / "two.yaml"
    cam = ("{type: camera, name: camera, width: 64, height: 48, horizontal_fov_deg: 70, rate_hz: 10, "
           "streams: [rgb], mount: {position: [0.3, 0.0, 1.3]}}")  # fmt: skip
    scenario.write_text(
        "version: 1\nname: two\nvessels:\n"
        f"  - {{name: wamv, model: wamv, sensors: [{cam}]}}\n"
        f"  - {{name: otter, model: otter, pose: {{position: [8.0, 1.0, 0.0], yaw_deg: 90.0}}, sensors: [{cam}]}}\n"
        "objects:\n  - {type: buoy, name: red_1, position: [6.0, -1.0, 0.0], color: red}\n"
    )
    root = generate(DatasetSpec(str(scenario), 1, tmp_path / "s", splits=(1.0, 0.0, 0.0)))
    coco = json.loads((root / "annotations" / "train.json").read_text())
    names = [image["file_name"] for image in coco["images"]]
    assert names == ["train/000000_wamv-camera.png", "train/000000_otter-camera.png"]
    assert sorted(p.name for p in (root / "images" / "train").iterdir()) == [n[6:] for n in sorted(names)]
    for vessel in ("wamv", "otter"):
        meta = json.loads((root / "meta" / f"000000_{vessel}-camera.json").read_text())
        assert meta["camera"] == f"{vessel}/camera"
        assert (root / "labels" / "train" / f"000000_{vessel}-camera.txt").is_file()
        assert (root / "masks" / "instance" / "train" / f"000000_{vessel}-camera.png").is_file()


def test_scene_randomization_moves_every_cameras_vessel(tmp_path):
    """Only the first camera's vessel was moved and turned: the otter's camera saw the scene from the same place
    in every frame (qa20). Each camera's vessel now gets its own drawn offset and yaw."""
    scenario = tmp_path / "two.yaml"
    cam = "{type: camera, name: camera, width: 32, height: 24, rate_hz: 10, streams: [rgb]}"
    scenario.write_text(
        "version: 1\nname: two\nvessels:\n"
        f"  - {{name: wamv, model: wamv, sensors: [{cam}]}}\n"
        f"  - {{name: otter, model: otter, pose: {{position: [8.0, 1.0, 0.0], yaw_deg: 90.0}}, sensors: [{cam}]}}\n"
    )
    rnd = tmp_path / "r.yaml"
    rnd.write_text("version: 1\nscene:\n  vessel_offset_m: {uniform: [-3, 3]}\n  vessel_yaw_deg: {uniform: [-40, 40]}\n")
    moved = generate(DatasetSpec(str(scenario), 1, tmp_path / "a", randomize=str(rnd), settle_s=0.0, formats=("yolo",)))
    still = generate(DatasetSpec(str(scenario), 1, tmp_path / "b", settle_s=0.0, formats=("yolo",)))
    a = json.loads((moved / "meta" / "000000_wamv-camera.json").read_text())
    b = json.loads((still / "meta" / "000000_wamv-camera.json").read_text())
    offsets, yaws = a["scene"]["vessel_offset_m"], a["scene"]["vessel_yaw_deg"]
    assert set(offsets) == set(yaws) == {"wamv", "otter"} and offsets["wamv"] != offsets["otter"]
    from usvsim.simulation import Simulation

    sim = Simulation.from_scenario(str(scenario))
    for vessel in ("wamv", "otter"):  # the free joint's position: the body origin, which the turn does not move
        adr = sim.model.jnt_qposadr[sim.model.body_jntadr[sim.vessels[vessel].index + 1]]
        shift = np.subtract(a["qpos"][adr : adr + 2], b["qpos"][adr : adr + 2])
        assert shift == pytest.approx(offsets[vessel], abs=1e-9)
        qa, qb = (np.array(m["vessels"][vessel]["quat_wxyz"]) for m in (a, b))
        turn = 2.0 * math.degrees(math.atan2(np.linalg.norm(np.cross(qb[1:], qa[1:]) + qb[0] * qa[1:] - qa[0] * qb[1:]),
                                             float(qa @ qb)))  # fmt: skip
        assert turn == pytest.approx(abs(yaws[vessel]), abs=1e-6)
    sim.close()


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--resolution", "640by480"], "--resolution '640by480': give WIDTHxHEIGHT"),
        (["--splits", "0.5,0.5"], "--splits '0.5,0.5': give three fractions train,val,test"),
        (["--out", ""], "--out is empty"),
    ],
)
def test_a_bad_resolution_splits_or_empty_out_is_named(tmp_path, monkeypatch, args, words):
    """One message said '--resolution is WIDTHxHEIGHT and --splits three fractions' whichever was wrong, and an
    empty --out (an unset shell variable) wrote the data set into the current folder (QA)."""
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["dataset", "buoy_field", "--frames", "1", "--out", "s", *args])
    assert result.exit_code == 2
    (line,) = [ln for ln in result.output.splitlines() if ln.strip()]
    assert line.startswith("usvsim: error: ") and words in line
    assert list(tmp_path.iterdir()) == []


def test_an_episodes_frames_share_one_split(tmp_path):
    """Splits were drawn per frame, so an episode's frames, near-duplicates 0.2 s apart, went to train and val
    alike (QA: seed 1, frames_per_episode 3: frame 0 in val, frames 1 and 2 in train), leaking val into train."""
    rnd = tmp_path / "r.yaml"
    rnd.write_text("version: 1\nper: episode\nframes_per_episode: 3\nlook: {sun.elevation_deg: {uniform: [10, 60]}}\n")
    root = generate(DatasetSpec("buoy_field", 9, tmp_path / "s", formats="coco", seed=2, randomize=str(rnd),
                                resolution=(64, 48), splits=(0.5, 0.5, 0.0)))  # fmt: skip
    metas = [json.loads((root / "meta" / f"{i:06d}.json").read_text()) for i in range(9)]
    episodes = [{m["split"] for m in metas[e : e + 3]} for e in (0, 3, 6)]
    assert all(len(s) == 1 for s in episodes) and set.union(*episodes) == {"train", "val"}
    for m in metas:
        assert (root / "images" / m["split"] / f"{m['frame']:06d}.png").is_file()


@pytest.mark.parametrize(
    ("scene", "shown"),
    [("buoy_offset_m: {choice: [a, b]}", "'a'"), ("vessel_yaw_deg: [1, 2]", "(1.0, 2.0)"), ("camera_height_m: true", "True")],
)
def test_a_scene_value_that_is_no_number_is_one_line(tmp_path, scene, shown):
    """`scene: {buoy_offset_m: {choice: [a, b]}}` passed the checks and stopped the first frame with numpy's
    UFuncTypeError traceback (exit 1), leaving an empty set folder behind (QA)."""
    (tmp_path / "r.yaml").write_text(f"version: 1\nscene:\n  {scene}\n")
    with pytest.raises(UsvsimError) as e:
        load_randomization(tmp_path / "r.yaml")
    key = scene.split(":")[0]
    assert str(e.value).startswith(f"randomization {tmp_path / 'r.yaml'}: scene.{key}: {shown} is not a number")
    args = ["dataset", "buoy_field", "--frames", "1", "--resolution", "64x48", "--out", str(tmp_path / "s")]
    result = CliRunner().invoke(app, [*args, "--randomize", str(tmp_path / "r.yaml")])
    assert result.exit_code == 2 and "is not a number" in result.output and not (tmp_path / "s").exists()
    (tmp_path / "ok.yaml").write_text("version: 1\nscene:\n  vessel_yaw_deg: {choice: [1, 2.5]}\n")
    assert load_randomization(tmp_path / "ok.yaml").scene["vessel_yaw_deg"].choice == (1, 2.5)


@pytest.mark.parametrize(
    ("scene", "words"),
    [("camera_pitch_deg: 200", "camera_pitch_deg: 200 is outside -90..90"),
     ("camera_pitch_deg: {uniform: [-300, 0]}", "camera_pitch_deg: -300 is outside -90..90"),
     ("vessel_yaw_deg: {normal: [0, 5], clip: [-400, 10]}", "vessel_yaw_deg: -400 is outside -360..360"),
     ("vessel_offset_m: 1.0e+9", "vessel_offset_m: 1e[+]09 is outside -1000..1000"),
     ("buoy_offset_m: {normal: [2000, 1]}", "buoy_offset_m: 2000 is outside -1000..1000"),
     ("camera_height_m: {choice: [0, -50]}", "camera_height_m: -50 is outside -20..20")],
)  # fmt: skip
def test_a_scene_value_out_of_its_bounds_is_one_line(tmp_path, scene, words):
    """Scene values had no bounds: a camera pitched 200° (upside down), an offset of 1e9 m were rendered
    without a word, and a buoy moved 1e7 m made MuJoCo diverge (qa20)."""
    (tmp_path / "r.yaml").write_text(f"version: 1\nscene:\n  {scene}\n")
    with pytest.raises(UsvsimError, match=f"^randomization {tmp_path / 'r.yaml'}: scene.{words} [(]"):
        load_randomization(tmp_path / "r.yaml")
    args = ["dataset", "buoy_field", "--frames", "1", "--resolution", "64x48", "--out", str(tmp_path / "s")]
    result = CliRunner().invoke(app, [*args, "--randomize", str(tmp_path / "r.yaml")])
    assert result.exit_code == 2 and "is outside" in result.output and not (tmp_path / "s").exists()


def test_a_scene_draw_out_of_bounds_stops_the_run_naming_it(tmp_path):
    """A normal without clip is checked by its mean; a draw past the bounds stops the run with one line."""
    (tmp_path / "r.yaml").write_text("version: 1\nscene:\n  camera_pitch_deg: {normal: [0, 1000]}\n")
    assert load_randomization(tmp_path / "r.yaml").scene["camera_pitch_deg"].normal == (0, 1000)
    with pytest.raises(UsvsimError, match=r"scene.camera_pitch_deg: -?[0-9.]+ is outside -90..90 .*\(drawn; give the "
                                          r"normal a clip: \[low, high\]\); stopped at frame 0"):  # fmt: skip
        generate(DatasetSpec("buoy_field", 3, tmp_path / "set", randomize=str(tmp_path / "r.yaml"), resolution=(64, 48)))


def test_an_environment_range_reaching_past_a_bound_is_refused_whatever_the_seed(tmp_path):
    """`wind.speed_mps: {uniform: [-5, 3]}` ran with seeds 4 and 5 (their draws were positive) and stopped with
    seeds 1-3: every end of an environment range is checked now, as the look's are (qa20)."""
    (tmp_path / "r.yaml").write_text("version: 1\nenvironment:\n  wind.speed_mps: {uniform: [-5, 3]}\n")
    for seed, words in ((1, "the drawn values make"), (4, r"wind.speed_mps: -5.0 \(an end of its range\) makes")):
        with pytest.raises(UsvsimError, match=rf"environment: {words} the scenario's environment.wind.speed_mps invalid"):
            generate(DatasetSpec("buoy_field", 1, tmp_path / "s", seed=seed, randomize=str(tmp_path / "r.yaml"),
                                 resolution=(64, 48)))  # fmt: skip
        assert not (tmp_path / "s").exists()


def test_generate_refuses_a_folder_holding_a_set_unless_forced(tmp_path):
    """generate() wrote a 2-frame set over a 4-frame one without a word: frames 2 and 3 stayed in images/ and
    labels/ beside annotations listing 2 images (QA; the CLI refused, and the detection-robustness experiment,
    re-run with fewer frames, trained on the stale ones). Now refused as by the CLI; force=True replaces it."""
    spec = DatasetSpec("buoy_field", 3, tmp_path / "s", formats="yolo,coco", resolution=(64, 48), splits=(1, 0, 0))
    generate(spec)
    small = DatasetSpec("buoy_field", 1, tmp_path / "s", formats="yolo,coco", resolution=(64, 48), splits=(1, 0, 0))
    with pytest.raises(UsvsimError, match="already holds a data set .*pass --force"):
        generate(small)
    assert len(list((tmp_path / "s" / "images" / "train").iterdir())) == 3
    root = generate(small, force=True)
    assert [p.name for p in (root / "images" / "train").iterdir()] == ["000000.png"]
    assert [p.name for p in (root / "labels" / "train").iterdir()] == ["000000.txt"]
    assert len(json.loads((root / "annotations" / "train.json").read_text())["images"]) == 1


def _random_instances(rng, h, w, n):
    """An instance image of n noisy blobs (holes, diagonal contacts, parts) and their labels (boxes from pixels)."""
    import cv2

    from usvsim.datasets.labels import ObjectLabel

    instance = np.zeros((h, w), np.uint16)
    labels = []
    for k in range(1, n + 1):
        x0, y0 = rng.integers(0, w - 4), rng.integers(0, h - 4)
        x1, y1 = rng.integers(x0 + 1, min(w, x0 + 40) + 1), rng.integers(y0 + 1, min(h, y0 + 30) + 1)
        blob = (rng.random((y1 - y0, x1 - x0)) < rng.uniform(0.3, 0.9)).astype(np.uint8)
        if rng.random() < 0.5:
            blob = cv2.medianBlur(blob * 255, 3) // 255
        instance[y0:y1, x0:x1][blob > 0] = k
    for k in range(1, n + 1):
        ys, xs = np.nonzero(instance == k)
        if len(xs):
            box = (float(xs.min()), float(ys.min()), float(xs.max() + 1), float(ys.max() + 1))
            labels.append(ObjectLabel(k, f"o{k}", "buoy_red", box, box, len(xs), 1.0, False))
    return instance, labels


@pytest.mark.parametrize("kind", ["rle", "compressed_rle", "polygon"])
def test_every_coco_segmentation_gives_the_mask_back_through_pycocotools(kind):
    """COCO segmentation was only uncompressed RLE: Detectron2's default (polygon masks) and Ultralytics' COCO
    converter need polygons (qa20). Each form decodes with pycocotools to exactly the object's pixels, holes and
    separate parts included; compressed RLE equals pycocotools' own encoding."""
    from pycocotools import mask as mask_utils

    from usvsim.datasets.writers import coco_segmentation

    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(30):
        h, w = (int(v) for v in rng.integers(8, 90, 2))
        instance, labels = _random_instances(rng, h, w, int(rng.integers(1, 6)))
        for lab in labels:
            seg = coco_segmentation(kind, instance, lab, (h, w))
            rle = mask_utils.merge(mask_utils.frPyObjects(seg, h, w)) if kind == "polygon" else (
                mask_utils.frPyObjects(seg, h, w) if kind == "rle" else {**seg, "counts": seg["counts"].encode()})  # fmt: skip
            mask = instance == lab.instance
            assert np.array_equal(mask_utils.decode(rle).astype(bool), mask)
            assert int(mask_utils.area(rle)) == lab.visible_pixels
            if kind == "compressed_rle":
                assert seg["counts"] == mask_utils.encode(np.asfortranarray(mask.astype(np.uint8)))["counts"].decode()
            if kind == "polygon":
                assert all(len(p) >= 6 and len(p) % 2 == 0 for p in seg)
            checked += 1
    assert checked > 60


def test_a_polygon_coco_set_reads_back_with_pycocotools(tmp_path):
    from pycocotools.coco import COCO

    root = generate(DatasetSpec("buoy_field", 2, tmp_path / "s", resolution=(160, 120), splits=(1.0, 0.0, 0.0),
                                min_visible_pixels=4, coco_segmentation="polygon"))  # fmt: skip
    coco = COCO(str(root / "annotations" / "train.json"))
    anns = coco.loadAnns(coco.getAnnIds())
    assert len(anns) >= 2 and all(isinstance(a["segmentation"], list) for a in anns)
    for ann in anns:
        info = coco.loadImgs(ann["image_id"])[0]
        inst = np.array(Image.open(root / "masks" / "instance" / info["file_name"]))
        assert np.array_equal(inst == ann["instance"], coco.annToMask(ann).astype(bool))
        assert int(coco.annToMask(ann).sum()) == ann["area"]
    assert json.loads((root / "dataset.json").read_text())["coco_segmentation"] == "polygon"
    result = CliRunner().invoke(app, ["dataset", "buoy_field", "--out", str(tmp_path / "z"), "--coco-segmentation", "poly"])
    assert result.exit_code == 2 and "--coco-segmentation: 'poly' is not one of rle, compressed_rle, polygon" in result.output


# Ultralytics' segment label line (docs.ultralytics.com/datasets/segment): `<class-index> <x1> <y1> ... <xn> <yn>`,
# at least 3 points, coordinates normalized to [0, 1] by the image's width and height, space-separated
_UNIT = r"(?:0(?:\.\d+)?|1(?:\.0+)?)"
_SEGMENT_LINE = rf"(\d+)((?: {_UNIT} {_UNIT}){{3,}})"


def _segment_points(line: str, w: int, h: int) -> tuple[int, np.ndarray]:
    """(class, pixel-edge points (N, 2)) of a label line that must follow Ultralytics' segment grammar."""
    import re

    match = re.fullmatch(_SEGMENT_LINE, line)
    assert match, f"not an Ultralytics segment line: {line[:80]!r}"
    return int(match[1]), np.array(match[2].split(), float).reshape(-1, 2) * (w, h)


def _fill(points: np.ndarray, h: int, w: int) -> tuple[np.ndarray, np.ndarray]:
    """The polygon drawn back (pycocotools, exact even-odd area; OpenCV's fillPoly on int32 pixel coordinates,
    as Ultralytics' polygon2mask draws it, edges included)."""
    import cv2
    from pycocotools import mask as mask_utils

    coco = mask_utils.decode(mask_utils.frPyObjects([points.ravel().tolist()], h, w))[:, :, 0].astype(bool)
    cv = np.zeros((h, w), np.uint8)
    cv2.fillPoly(cv, [points.astype(np.int32)], 1)
    return coco, cv.astype(bool)


def test_yolo_segment_lines_follow_ultralytics_grammar_and_draw_the_masks_back():
    """YOLO labels were boxes only: Ultralytics' segmentation models need `class x1 y1 ...` polygon lines (qa24).
    One line per object, holes and separate parts joined into one polygon by bridges walked there and back:
    pycocotools draws exactly the object's pixels from it; OpenCV's fillPoly (Ultralytics) draws them all and,
    for a mask of one part without holes, nothing else (a bridge's own pixels are the only extra ones)."""
    import cv2

    from usvsim.datasets.writers import yolo_line

    rng = np.random.default_rng(11)
    checked = simple = 0
    for _ in range(30):
        h, w = (int(v) for v in rng.integers(8, 90, 2))
        instance, labels = _random_instances(rng, h, w, int(rng.integers(1, 6)))
        for lab in labels:
            line = yolo_line("segment", instance, lab, (h, w))
            cls, points = _segment_points(line, w, h)
            mask = instance == lab.instance
            coco, cv = _fill(points, h, w)
            assert cls == DETECTABLE.index(lab.category) and np.array_equal(coco, mask) and not (mask & ~cv).any()
            x0, y0, x1, y1 = lab.visible_box  # the outline runs a quarter pixel inside the box's edges
            assert np.allclose(points.min(0), (x0 + 0.25, y0 + 0.25), atol=5e-4 * max(w, h))
            assert np.allclose(points.max(0), (x1 - 0.25, y1 - 0.25), atol=5e-4 * max(w, h))
            _, hierarchy = cv2.findContours(mask.astype(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
            if len(hierarchy[0]) == 1:
                assert np.array_equal(cv, mask)
                simple += 1
            checked += 1
    assert checked > 60 and simple > 5
    box = yolo_line("box", instance, labels[0], (h, w)).split()
    assert len(box) == 5


def test_a_yolo_segment_set(tmp_path):
    root = generate(DatasetSpec("buoy_field", 2, tmp_path / "s", ("yolo", "masks"), resolution=(160, 120),
                                splits=(1.0, 0.0, 0.0), min_visible_pixels=4, yolo_labels="segment"))  # fmt: skip
    data_yaml = (root / "data.yaml").read_text()
    assert data_yaml.startswith("# labels: segment") and yaml.safe_load(data_yaml)["names"][0] == DETECTABLE[0]
    lines = 0
    for label in sorted((root / "labels" / "train").glob("*.txt")):
        inst = np.array(Image.open(root / "masks" / "instance" / "train" / f"{label.stem}.png"))
        objects = json.loads((root / "meta" / f"{label.stem}.json").read_text())["objects"]
        rows = label.read_text().splitlines()
        assert len(rows) == len(objects)
        for row, obj in zip(rows, objects, strict=True):
            cls, points = _segment_points(row, 160, 120)
            coco, cv = _fill(points, 120, 160)
            mask = inst == obj["instance"]
            assert cls == DETECTABLE.index(obj["category"]) and np.array_equal(coco, mask) and not (mask & ~cv).any()
            lines += 1
    assert lines >= 4 and json.loads((root / "dataset.json").read_text())["yolo_labels"] == "segment"
    runner = CliRunner()
    result = runner.invoke(app, ["dataset", "buoy_field", "--out", str(tmp_path / "z"), "--yolo-labels", "polygon"])
    assert result.exit_code == 2 and "--yolo-labels: 'polygon' is not one of box, segment" in result.output
    result = runner.invoke(app, ["dataset", "buoy_field", "--out", str(tmp_path / "z"), "--format", "coco",
                                 "--yolo-labels", "segment"])  # fmt: skip
    assert result.exit_code == 2 and "--yolo-labels segment needs yolo in --format (got coco)" in result.output
    assert not (tmp_path / "z").exists()
