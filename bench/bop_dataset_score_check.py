#!/usr/bin/python3
"""Holds vscan's dataset scoring (JobService.ScoreDatasetResults) against the BOP toolkit's own code.

A small dataset is written by a dataset job on vscand (two bins: angle blocks; tubes with angle
blocks; several views a scene). The tube's axis is declared a continuous symmetry in the stored
models/models_info.json (the job writes none), so that it is scored with ADD-S, and 15% of the
true instances get a visib_fract below, at or just above the 0.1 cut in the stored
scene_gt_info.json (these bins leave every part more than 10% visible). A results CSV is
made from the ground truth: per true instance an estimate that is exact, a little off, far off,
turned, turned about the tube's axis (symmetric-equivalent), or missing, some duplicated with other
scores (ties too), estimates of part types an image does not hold, and rows for images the dataset
lacks. It is scored by `vscan dataset score --json` and by bop_toolkit_lib with the steps of its
evaluation scripts (eval_calc_errors, eval_calc_scores; not in the reference copy) written here:
inout.load_bop_results, load_scene_gt, load_ply; per image and object the estimates sorted by
score and cut to the valid instances (visib_fract >= 0.1, n_top = -1); pose_error.add or adi (adi
when models_info declares a symmetry) and mssd over misc.get_symmetry_transformations(info, 0.01);
errors divided by models_info's diameter; pose_matching.match_poses_scene;
score.calc_localization_scores at 0.1 and at each of np.arange(0.05, 0.51, 0.05), the MSSD
recalls averaged. Exits 1 when a recall or count differs.

  /usr/bin/python3 bench/bop_dataset_score_check.py [--seeds 2] [--views 2] [--seed 1]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import types

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
PARTS = os.path.join(SOURCE, "data", "parts")
TUBE_OBJ = 2  # part types are numbered in the plan's order: angle block 1, tube 2


def plan_text(seeds, views):
    text = f"""name: score-check
bins:
  - name: blocks
    bin: {{inner_size: [0.20, 0.15, 0.10]}}
    parts:
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 8}}
    max_simulated_s: 4
  - name: rods
    bin: {{inner_size: [0.25, 0.20, 0.10]}}
    parts:
      - {{mesh: {PARTS}/round.stl, unit: cm, scale: 0.25, count: 5}}
      - {{mesh: {PARTS}/angle_block.STL, unit: in, count: 3}}
    max_simulated_s: 4
seeds: {{first: 1, count: {seeds}}}
sensors:
  - {{name: tof, preset: kinect-v2-class, width: 256, height: 212}}
"""
    if views > 1:
        text += f"views: {{count: {views}, cone_deg: 25, distance_m: [0.6, 0.75]}}\n"
    return text


def find_toolkit():
    """$VSCAN_BOP_TOOLKIT, else shared/tools/bop_toolkit in a folder above the repository; None
    when there is none."""
    given = os.environ.get("VSCAN_BOP_TOOLKIT")
    if given:
        return given if os.path.isdir(os.path.join(given, "bop_toolkit_lib")) else None
    folder = SOURCE
    while os.path.dirname(folder) != folder:
        folder = os.path.dirname(folder)
        candidate = os.path.join(folder, "shared", "tools", "bop_toolkit")
        if os.path.isdir(os.path.join(candidate, "bop_toolkit_lib")):
            return candidate
    return None


def load_toolkit(path=None):
    """bop_toolkit_lib's inout, misc, pose_error, pose_matching and score; stand-ins for the image
    modules inout imports and nothing here uses (Debian 12 ships neither imageio.v2 nor png)."""
    try:
        import imageio
        sys.modules.setdefault("imageio.v2", getattr(imageio, "v2", imageio))
    except ImportError:
        stand_in = types.ModuleType("imageio")
        sys.modules["imageio"] = sys.modules["imageio.v2"] = stand_in
    try:
        import png  # noqa: F401
    except ImportError:
        sys.modules["png"] = types.ModuleType("png")
    try:
        import scipy.spatial  # noqa: F401
    except ImportError:
        stand_in_scipy()
    path = path or find_toolkit()
    if path is None:
        raise ImportError("no bop_toolkit: set VSCAN_BOP_TOOLKIT or put it at shared/tools/bop_toolkit above the "
                          "repository")
    sys.path.insert(0, path)
    from bop_toolkit_lib import inout, misc, pose_error, pose_matching, score
    return types.SimpleNamespace(inout=inout, misc=misc, pose_error=pose_error, pose_matching=pose_matching,
                                 score=score)


class BruteForceTree:
    """scipy.spatial.cKDTree's query(points, k=1) by comparing every pair: the same exact nearest
    neighbours, for pose_error.adi where scipy is not installed."""

    def __init__(self, pts):
        self.pts = np.asarray(pts, np.float64)

    def query(self, queries, k=1):
        queries = np.asarray(queries, np.float64)
        dists, index = np.empty(len(queries)), np.empty(len(queries), np.int64)
        for i in range(0, len(queries), 512):
            d = np.linalg.norm(queries[i:i + 512, None, :] - self.pts[None, :, :], axis=2)
            index[i:i + 512] = np.argmin(d, axis=1)
            dists[i:i + 512] = d[np.arange(len(d)), index[i:i + 512]]
        return dists, index


def stand_in_scipy():
    """scipy.spatial with cKDTree by brute force, and an empty scipy.spatial.distance (misc imports
    it; its calc_pts_diameter is not used here: the diameter is models_info.json's)."""
    scipy = types.ModuleType("scipy")
    spatial = types.ModuleType("scipy.spatial")
    distance = types.ModuleType("scipy.spatial.distance")
    scipy.spatial, spatial.distance, spatial.cKDTree = spatial, distance, BruteForceTree
    sys.modules.update({"scipy": scipy, "scipy.spatial": spatial, "scipy.spatial.distance": distance})


def declare_tube_axis(root, bop, obj_id=TUBE_OBJ):
    """Declares the tube's axis (its vertices' longest principal axis through their centroid) a
    continuous symmetry in models_info.json; returns (axis, point) in mm."""
    pts = bop.inout.load_ply(os.path.join(root, "models", "obj_%06d.ply" % obj_id))["pts"].astype(np.float64)
    centre = pts.mean(axis=0)
    _, _, vt = np.linalg.svd(pts - centre, full_matrices=False)
    axis = vt[0] / np.linalg.norm(vt[0])
    path = os.path.join(root, "models", "models_info.json")
    with open(path) as f:
        info = json.load(f)
    info[str(obj_id)]["symmetries_continuous"] = [{"axis": axis.tolist(), "offset": centre.tolist()}]
    with open(path, "w") as f:
        json.dump(info, f)
    return axis, centre


def lower_visibility(root, rng, share=0.15):
    """Sets some true instances' visib_fract in the stored scene_gt_info.json below, at and just
    above the 0.1 cut (these small bins leave every part more than 10% visible); returns how many."""
    changed = 0
    for scene in sorted(os.listdir(os.path.join(root, "train_pbr"))):
        path = os.path.join(root, "train_pbr", scene, "scene_gt_info.json")
        with open(path) as f:
            info = json.load(f)
        for entries in info.values():
            for entry in entries:
                if rng.random() < share:
                    entry["visib_fract"] = float(rng.choice([0.0, 0.05, 0.09999, 0.1, 0.10001]))
                    changed += 1
        with open(path, "w") as f:
            json.dump(info, f)
    return changed


def read_dataset(root, bop):
    models_info = bop.inout.load_json(os.path.join(root, "models", "models_info.json"), keys_to_int=True)
    models = {}
    for obj_id, info in models_info.items():
        pts = bop.inout.load_ply(os.path.join(root, "models", "obj_%06d.ply" % obj_id))["pts"].astype(np.float64)
        models[obj_id] = {"pts": pts, "diameter": info["diameter"], "centre": pts.mean(axis=0),
                          "syms": bop.misc.get_symmetry_transformations(info, 0.01),
                          "symmetric": "symmetries_discrete" in info or "symmetries_continuous" in info}
    with open(os.path.join(root, "dataset.json")) as f:
        scene_count = json.load(f)["scene_count"]
    scenes = {}
    for scene_id in range(scene_count):
        d = os.path.join(root, "train_pbr", "%06d" % scene_id)
        scenes[scene_id] = (bop.inout.load_scene_gt(os.path.join(d, "scene_gt.json")),
                            bop.inout.load_json(os.path.join(d, "scene_gt_info.json"), keys_to_int=True))
    return models, scenes


def rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def make_results(rng, models, scenes, tube_axis):
    """The CSV text and what kinds of estimate it holds."""
    rows, kinds = [], {}

    def add(scene_id, im_id, obj_id, score, R, t):
        rows.append(f"{scene_id},{im_id},{obj_id},{score!r},{' '.join(repr(float(v)) for v in R.ravel())},"
                    f"{' '.join(repr(float(v)) for v in np.ravel(t))},-1")

    def score():
        return float(rng.choice([round(rng.uniform(0, 1), 2), 0.5]))

    for scene_id, (scene_gt, _) in scenes.items():
        for im_id, gts in scene_gt.items():
            present = {gt["obj_id"] for gt in gts}
            for gt in gts:
                obj_id, m = gt["obj_id"], models[gt["obj_id"]]
                R, t, d, c = gt["cam_R_m2c"], gt["cam_t_m2c"].ravel(), m["diameter"], m["centre"]
                kind = rng.choice(["exact", "near", "off", "turned", "symmetric", "missing"],
                                  p=[0.1, 0.2, 0.2, 0.1, 0.3, 0.1] if obj_id == TUBE_OBJ else
                                  [0.2, 0.25, 0.25, 0.2, 0, 0.1])
                kinds[kind] = kinds.get(kind, 0) + 1
                if kind == "missing":
                    continue
                for copy in range(1 + int(rng.random() < 0.25)):
                    Re, te = R.copy(), t.copy()
                    if kind == "exact":
                        te = te + rng.normal(size=3) * 0.05
                    elif kind == "near":
                        te = te + rng.normal(size=3) / np.sqrt(3) * d * rng.uniform(0.01, 0.12)
                    elif kind == "off":
                        te = te + rng.normal(size=3) / np.sqrt(3) * d * rng.uniform(0.1, 0.6)
                    elif kind == "turned":  # about the part's centre
                        turn = rotation(rng.normal(size=3), np.radians(rng.uniform(1, 30)))
                        Re, te = R @ turn, t + R @ (c - turn @ c)
                    else:  # about the tube's axis: the same tube
                        axis, point = tube_axis
                        turn = rotation(axis, rng.uniform(0, 2 * np.pi))
                        Re, te = R @ turn, t + R @ (point - turn @ point) + rng.normal(size=3) * 0.2
                    if copy:  # a duplicate, further off
                        te = te + rng.normal(size=3) * d * 0.1
                    add(scene_id, im_id, obj_id, score(), Re, te)
            for obj_id in models:
                if obj_id not in present and rng.random() < 0.5:  # a part type the image does not hold
                    gt = gts[rng.integers(len(gts))] if gts else None
                    t = gt["cam_t_m2c"].ravel() if gt else np.array([0.0, 0, 600])
                    add(scene_id, im_id, obj_id, score(), np.eye(3), t + rng.normal(size=3) * 5)
                    kinds["absent part"] = kinds.get("absent part", 0) + 1
    for scene_id, im_id in ((max(scenes) + 7, 0), (0, 999)):  # images the dataset does not have
        add(scene_id, im_id, min(models), 0.9, np.eye(3), np.array([0.0, 0, 500]))
        kinds["unknown image"] = kinds.get("unknown image", 0) + 1
    order = rng.permutation(len(rows))
    return "scene_id,im_id,obj_id,score,R,t,time\n" + "\n".join(rows[i] for i in order) + "\n", kinds


def bop_scores(bop, models, scenes, results_path):
    """Overall, per-object and per-scene ADD(-S) recall and MSSD recalls, as BOP computes them."""
    ests = bop.inout.load_bop_results(results_path)
    by_image = {}
    for est_id, e in enumerate(ests):
        by_image.setdefault((e["scene_id"], e["im_id"]), {}).setdefault(e["obj_id"], []).append((est_id, e))
    errs = {}  # scene_id -> list of per-estimate errors (eval_calc_errors' output)
    valid_of = {}
    for scene_id, (scene_gt, scene_gt_info) in scenes.items():
        valid_of[scene_id] = {im: [i["visib_fract"] >= 0.1 for i in scene_gt_info[im]] for im in scene_gt}
        for im_id, gts in scene_gt.items():
            valid = valid_of[scene_id][im_id]
            for obj_id, obj_ests in by_image.get((scene_id, im_id), {}).items():
                inst_count = sum(1 for g, gt in enumerate(gts) if gt["obj_id"] == obj_id and valid[g])
                if inst_count == 0:
                    continue  # not a target of the image
                m = models[obj_id]
                kept = sorted(obj_ests, key=lambda x: x[1]["score"], reverse=True)[:inst_count]
                for est_id, e in kept:
                    ad, mssd = {}, {}
                    for g, gt in enumerate(gts):
                        if gt["obj_id"] != obj_id:
                            continue
                        Rg, tg = gt["cam_R_m2c"], gt["cam_t_m2c"]
                        f = bop.pose_error.adi if m["symmetric"] else bop.pose_error.add
                        ad[g] = f(e["R"], e["t"], Rg, tg, m["pts"])
                        mssd[g] = bop.pose_error.mssd(e["R"], e["t"], Rg, tg, m["pts"], m["syms"])
                    errs.setdefault(scene_id, []).append(
                        {"im_id": im_id, "obj_id": obj_id, "est_id": est_id, "score": e["score"],
                         "ad": ad, "mssd": mssd, "gt_visib_fracts": {g: scenes[scene_id][1][im_id][g]["visib_fract"]
                                                                    for g in ad}})

    def recalls(kind, threshold):
        matches = []
        for scene_id, (scene_gt, scene_gt_info) in scenes.items():
            scene_errs = [{"im_id": e["im_id"], "obj_id": e["obj_id"], "est_id": e["est_id"], "score": e["score"],
                           "errors": {g: [err / models[e["obj_id"]]["diameter"]] for g, err in e[kind].items()},
                           "gt_visib_fracts": e["gt_visib_fracts"]} for e in errs.get(scene_id, [])]
            matches += bop.pose_matching.match_poses_scene(scene_id, scene_gt, scene_gt_info, valid_of[scene_id],
                                                           scene_errs, [threshold], -1)
        s = bop.score.calc_localization_scores(sorted(scenes), sorted(models), matches, -1, do_print=False)
        return s

    add = recalls("ad", 0.1)
    mssd = [recalls("mssd", t) for t in np.arange(0.05, 0.51, 0.05)]
    return {"add": add, "mssd": mssd, "estimates": len(ests), "gt_count": add["gt_count"],
            "targets": add["targets_count"]}


def compare(ours, theirs):
    """(name, ours, theirs) for every figure that differs by more than 1e-12."""
    diffs = []

    def check(name, a, b):
        if abs(float(a) - float(b)) > 1e-12:
            diffs.append((name, a, b))

    add, mssd = theirs["add"], theirs["mssd"]
    overall = ours["overall"]
    check("valid instances", overall.get("validInstances", 0), theirs["targets"])
    check("true instances", ours.get("trueInstances", 0), theirs["gt_count"])
    check("ADD(-S) correct", overall.get("addCorrect", 0), add["tp_count"])
    check("ADD(-S) recall", overall.get("addRecall", 0), add["recall"])
    for k, s in enumerate(mssd):
        check(f"MSSD recall at {0.05 + 0.05 * k:.2f}", overall["mssdRecalls"][k], s["recall"])
    check("MSSD average recall", overall.get("mssdAverageRecall", 0), np.mean([s["recall"] for s in mssd]))
    for obj in ours["objects"]:
        o, r = obj["objId"], obj["recall"]
        # BOP's recall is 0 for an object without targets; vscan leaves it unset.
        check(f"obj {o} ADD(-S) recall", r.get("addRecall", 0), add["obj_recalls"][o])
        check(f"obj {o} MSSD average recall", r.get("mssdAverageRecall", 0),
              np.mean([s["obj_recalls"][o] for s in mssd]))
    for scene in ours["scenes"]:
        i, r = scene.get("sceneId", 0), scene["recall"]
        check(f"scene {i} ADD(-S) recall", r.get("addRecall", 0), add["scene_recalls"][i])
        check(f"scene {i} MSSD average recall", r.get("mssdAverageRecall", 0),
              np.mean([s["scene_recalls"][i] for s in mssd]))
    check("objects listed", len(ours["objects"]), len(add["obj_recalls"]))
    check("scenes listed", len(ours["scenes"]), len(add["scene_recalls"]))
    return diffs


def vscan_score(vscan, address, job_id, csv_path):
    run = subprocess.run([vscan, "--server", address, "dataset", "score", job_id, "--results", csv_path, "--json"],
                         capture_output=True, text=True, timeout=300)
    if run.returncode != 0:
        raise RuntimeError(f"vscan dataset score failed ({run.returncode}): {run.stderr}")
    return json.loads(run.stdout)


def run_check(vscan, address, job_id, root, seed=1, workdir=None, bop=None):
    """Declares the tube's axis, writes the results, scores them both ways; returns a report dict."""
    bop = bop or load_toolkit()
    rng = np.random.default_rng(seed)
    tube_axis = declare_tube_axis(root, bop)
    lowered = lower_visibility(root, rng)
    models, scenes = read_dataset(root, bop)
    csv, kinds = make_results(rng, models, scenes, tube_axis)
    kinds["visib_fract lowered"] = lowered
    csv_path = os.path.join(workdir or root, "results.csv")
    with open(csv_path, "w") as f:
        f.write(csv)
    start = time.perf_counter()
    ours = vscan_score(vscan, address, job_id, csv_path)
    vscan_s = time.perf_counter() - start
    start = time.perf_counter()
    theirs = bop_scores(bop, models, scenes, csv_path)
    bop_s = time.perf_counter() - start
    return {"ours": ours, "theirs": theirs, "diffs": compare(ours, theirs), "kinds": kinds, "csv": csv_path,
            "vscan_s": vscan_s, "bop_s": bop_s}


def print_report(report):
    ours, theirs = report["ours"], report["theirs"]
    o = ours["overall"]
    print(f"{ours.get('sceneCount', 0)} scenes, {ours.get('imageCount', 0)} images, "
          f"{ours.get('trueInstances', 0)} true instances ({o.get('validInstances', 0)} valid); "
          f"{ours.get('rows', 0)} estimates ({ours.get('ignoredRows', 0)} for images not in the dataset); "
          f"kinds: {report['kinds']}")
    print(f"{'':22} {'vscan':>10} {'bop_toolkit':>12}")
    print(f"{'ADD(-S) recall':22} {o.get('addRecall', 0):10.4f} {theirs['add']['recall']:12.4f}")
    mssd = float(np.mean([s['recall'] for s in theirs['mssd']]))
    print(f"{'MSSD average recall':22} {o.get('mssdAverageRecall', 0):10.4f} {mssd:12.4f}")
    for obj in ours["objects"]:
        i = obj["objId"]
        add_s = "ADD-S" if obj.get("usesAddS") else "ADD"
        print(f"{'obj %d (%s)' % (i, add_s):22} {obj['recall'].get('addRecall', 0):10.4f} "
              f"{theirs['add']['obj_recalls'][i]:12.4f}")
    print(f"scored in {report['vscan_s']:.2f} s (vscan, CLI and server), {report['bop_s']:.2f} s (bop_toolkit_lib)")
    print("differences: " + (", ".join(f"{n}: {a} vs {b}" for n, a, b in report["diffs"]) or "none"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--views", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1, help="of the results drawn")
    parser.add_argument("--build", default=os.path.join(SOURCE, "build", "release"))
    args = parser.parse_args()
    os.environ.setdefault("VSCAN_BUILD_DIR", os.path.abspath(args.build))
    os.environ.setdefault("VSCAN_SOURCE_DIR", SOURCE)
    sys.path.insert(0, os.path.join(SOURCE, "tests", "integration"))
    from harness import VSCAN, Server  # noqa: E402

    with tempfile.TemporaryDirectory(prefix="vscan-score-check-") as tmp:
        server = Server(data_dir=tmp).start()
        try:
            plan = os.path.join(tmp, "plan.yaml")
            with open(plan, "w") as f:
                f.write(plan_text(args.seeds, args.views))
            start = time.perf_counter()
            run = subprocess.run([VSCAN, "--server", server.address, "dataset", "run", plan, "--watch"],
                                 capture_output=True, text=True, timeout=600)
            if run.returncode != 0:
                sys.exit(f"dataset job failed: {run.stderr}\n{server.log()}")
            job_id = (run.stdout + run.stderr).split("started dataset job ")[1].split()[0]
            print(f"dataset job {job_id} written in {time.perf_counter() - start:.1f} s")
            root = os.path.join(tmp, "store", "datasets", job_id)
            report = run_check(VSCAN, server.address, job_id, root, args.seed, tmp)
            print_report(report)
        finally:
            server.stop()
    sys.exit(1 if report["diffs"] else 0)


if __name__ == "__main__":
    main()
