#!/usr/bin/python3
"""Holds vscan's pose errors and scores against the BOP toolkit's own code on random cases.

Random parts (uneven point clouds, some declared symmetric; rings with a continuous symmetry about
an arbitrary line; boxes with discrete symmetries; rings with both), random true poses and
estimates at errors from 0.1% to 60% of the diameter (some through a symmetry), tied scores and
visibilities around the cut go to bench/bop_score_cases (vscan's localization library) and to
bop_toolkit_lib (pose_error.add, adi, mssd; misc.calc_pts_diameter and
get_symmetry_transformations; pose_matching.match_poses_scene; score.calc_localization_scores),
with BOP's evaluation steps around them: estimates sorted by score and cut to the number of valid
instances (n_top = -1) or all kept (n_top = 0), errors divided by the diameter, MSSD recall at
0.05..0.50 averaged. Prints the largest differences; exits 1 if any is above 1e-9.

  /usr/bin/python3 bench/bop_score_check.py --cases 300 --binary build/release/bench/bop_score_cases
"""

import argparse
import json
import subprocess
import sys
import time

import numpy as np

TOOLKIT = "/work/shared/tools/bop_toolkit"


def load_toolkit(path):
    sys.path.insert(0, path)
    from bop_toolkit_lib import misc, pose_error, pose_matching, score  # noqa: E402
    return misc, pose_error, pose_matching, score


def random_rotation(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def axis_angle(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def rigid(R, t):
    m = np.eye(4)
    m[:3, :3] = R
    m[:3, 3] = t
    return m


def rings(rng, radius, heights, counts):
    pts = []
    for h, n in zip(heights, counts):
        phase = rng.uniform(0, 2 * np.pi)
        a = phase + 2 * np.pi * np.arange(n) / n
        pts.append(np.stack([radius * np.cos(a), radius * np.sin(a), np.full(n, h)], axis=1))
    return np.concatenate(pts)


def make_part(rng, part_id):
    """Vertices (float32), discrete symmetries (4x4) and continuous ones (axis, point)."""
    kind = rng.choice(["uneven", "uneven_declared", "rings", "box", "rings_flip"])
    size = rng.uniform(0.04, 0.15)
    discrete, continuous = [], []
    if kind.startswith("uneven"):
        # A sparse body and a dense cluster in one corner: ADD-S depends on its direction here.
        body = rng.uniform(-size / 2, size / 2, size=(rng.integers(30, 200), 3))
        corner = size / 2 - rng.uniform(0, size / 5, size=(rng.integers(100, 500), 3))
        local = np.concatenate([body, corner])
        if kind == "uneven_declared":
            # Declared symmetric about z though the points are not (as a scanned part may be):
            # scored with ADD-S, where the direction decides.
            continuous = [(np.array([0.0, 0, 1]), np.zeros(3))]
    elif kind == "box":
        half = size / 2 * np.array([1.0, rng.uniform(0.3, 0.9), rng.uniform(0.1, 0.6)])
        p = rng.uniform(-half, half, size=(rng.integers(50, 300), 3))
        face = rng.integers(0, 3, size=len(p))
        p[np.arange(len(p)), face] = np.where(rng.random(len(p)) < 0.5, -1, 1) * half[face]
        # Symmetric copies under the three half turns, so that the declared symmetries hold.
        flips = [np.diag(d) for d in ([1, -1, -1], [-1, 1, -1], [-1, -1, 1])]
        local = np.concatenate([p] + [p @ f.T for f in flips])
        discrete = [rigid(f, np.zeros(3)) for f in flips]
    else:
        heights = rng.uniform(-size / 2, size / 2, size=rng.integers(2, 5))
        if kind == "rings_flip":
            heights = np.concatenate([heights, -heights])
        counts = rng.integers(8, 90, size=len(heights))
        if kind == "rings_flip":
            counts[len(counts) // 2:] = counts[:len(counts) // 2]
        local = rings(rng, size / 2 * rng.uniform(0.3, 1), heights, counts)
        continuous = [(np.array([0.0, 0, 1]), np.zeros(3))]
        if kind == "rings_flip":
            discrete = [rigid(np.diag([1.0, -1, -1]), np.zeros(3))]
    # The part frame is not the shape's: symmetries about lines off the origin, axes not along z.
    frame = rigid(random_rotation(rng), rng.uniform(-size, size, 3))
    verts = (local @ frame[:3, :3].T + frame[:3, 3]).astype(np.float32)
    inv = np.linalg.inv(frame)
    discrete = [frame @ s @ inv for s in discrete]
    continuous = [(frame[:3, :3] @ a, frame[:3, :3] @ p + frame[:3, 3]) for a, p in continuous]
    return {"id": part_id, "kind": kind, "verts": verts, "discrete": discrete, "continuous": continuous}


def symmetry_sample(rng, part):
    """One transform of the part's symmetry group (part frame), drawn at random."""
    s = np.eye(4)
    if part["discrete"] and rng.random() < 0.7:
        s = part["discrete"][rng.integers(len(part["discrete"]))]
    if part["continuous"]:
        a, p = part["continuous"][0]
        R = axis_angle(a, rng.uniform(0, 2 * np.pi))
        s = rigid(R, p - R @ p) @ s
    return s


def make_case(rng, case_index):
    parts = [make_part(rng, 10 * case_index + k + 1) for k in range(rng.integers(1, 4))]
    truth, estimates = [], []
    for part in parts:
        diameter = np.max(np.linalg.norm(part["verts"][:, None] - part["verts"][None], axis=2))
        for _ in range(rng.integers(0, 6)):
            pose = rigid(random_rotation(rng), rng.uniform(-0.3, 0.3, 3))
            visib = rng.choice([rng.uniform(0, 1), rng.uniform(0, 0.1), 0.1, 1.0], p=[0.6, 0.15, 0.1, 0.15])
            truth.append((part["id"], pose, float(visib)))
            for _ in range(rng.integers(0, 3)):
                # Off by 0.1% to 60% of the diameter, half of it turned about the part's centre.
                err = diameter * 10 ** rng.uniform(-3, np.log10(0.6))
                turn = axis_angle(rng.normal(size=3), rng.uniform(0, 1) * err / diameter * 2)
                centre = part["verts"].astype(float).mean(axis=0)
                delta = rigid(turn, centre - turn @ centre)
                delta[:3, 3] += rng.normal(size=3) / np.sqrt(3) * err * rng.uniform(0, 1)
                est = pose @ symmetry_sample(rng, part) @ delta
                estimates.append((part["id"], est, float(rng.choice([rng.uniform(0, 1), 0.5]))))
        for _ in range(rng.integers(0, 3)):  # estimates of nothing
            estimates.append((part["id"], rigid(random_rotation(rng), rng.uniform(-0.3, 0.3, 3)),
                              float(rng.uniform(0, 1))))
    order = rng.permutation(len(estimates))
    estimates = [estimates[i] for i in order]
    options = {"add_threshold": float(rng.choice([0.1, 0.1, 0.05, 0.2, 0.3])),
               "min_visible_fraction": float(rng.choice([0.1, 0.1, 0.0, 0.5])),
               "keep_top": bool(rng.random() < 0.7)}
    return {"parts": parts, "truth": truth, "estimates": estimates, "options": options}


def pose_tokens(m):
    return " ".join(repr(float(v)) for v in list(m[:3, :3].ravel()) + list(m[:3, 3]))


def case_text(case):
    out = [str(len(case["parts"]))]
    for part in case["parts"]:
        out.append(f"{part['id']} {len(part['verts'])}")
        out.append(" ".join(repr(float(v)) for v in part["verts"].ravel()))
        out.append(str(len(part["discrete"])))
        out += [pose_tokens(s) for s in part["discrete"]]
        out.append(str(len(part["continuous"])))
        out += [" ".join(repr(float(v)) for v in list(a) + list(p)) for a, p in part["continuous"]]
    out.append(str(len(case["truth"])))
    out += [f"{pid} {pose_tokens(m)} {repr(v)}" for pid, m, v in case["truth"]]
    out.append(str(len(case["estimates"])))
    out += [f"{pid} {pose_tokens(m)} {repr(s)}" for pid, m, s in case["estimates"]]
    o = case["options"]
    out.append(f"{repr(o['add_threshold'])} {repr(o['min_visible_fraction'])} {int(o['keep_top'])}")
    return "\n".join(out)


class Bop:
    """The case scored by bop_toolkit_lib, with the steps of its evaluation scripts around it."""

    def __init__(self, toolkit):
        self.misc, self.pose_error, self.pose_matching, self.score = toolkit

    def part_info(self, part):
        pts = part["verts"].astype(np.float64)
        info = {}
        if part["discrete"]:
            info["symmetries_discrete"] = [list(s.ravel()) for s in part["discrete"]]
        if part["continuous"]:
            info["symmetries_continuous"] = [{"axis": list(a), "offset": list(p)} for a, p in part["continuous"]]
        syms = self.misc.get_symmetry_transformations(info, 0.01)
        return pts, self.misc.calc_pts_diameter(pts), syms, bool(info)

    def pair_errors(self, pts, syms, est, gt):
        Re, te, Rg, tg = est[:3, :3], est[:3, 3:], gt[:3, :3], gt[:3, 3:]
        return (self.pose_error.add(Re, te, Rg, tg, pts), self.pose_error.adi(Re, te, Rg, tg, pts),
                self.pose_error.mssd(Re, te, Rg, tg, pts, syms))

    def match(self, case, errors, diameters, threshold):
        """Per true instance: the estimate matched to it (-1 for none), as eval_calc_scores."""
        o = case["options"]
        gts = [{"obj_id": pid} for pid, _, _ in case["truth"]]
        infos = [{"visib_fract": v} for _, _, v in case["truth"]]
        valid = [v >= o["min_visible_fraction"] for _, _, v in case["truth"]]
        scene_errs = []
        for part in case["parts"]:
            pid = part["id"]
            inst_count = sum(1 for g, (p, _, _) in enumerate(case["truth"]) if p == pid and valid[g])
            if inst_count == 0:
                continue  # no target: eval_calc_errors skips the part's estimates
            ests = [(i, s) for i, (p, _, s) in enumerate(case["estimates"]) if p == pid]
            ests = sorted(ests, key=lambda x: x[1], reverse=True)  # eval_calc_errors
            if o["keep_top"]:
                ests = ests[:inst_count]
            for i, s in ests:
                gt_ids = [g for g, (p, _, _) in enumerate(case["truth"]) if p == pid]
                scene_errs.append({"im_id": 0, "obj_id": pid, "est_id": i, "score": s,
                                   "errors": {g: [errors[(i, g)] / diameters[pid]] for g in gt_ids},
                                   "gt_visib_fracts": {g: infos[g]["visib_fract"] for g in gt_ids}})
        matches = self.pose_matching.match_poses_scene(0, {0: gts}, {0: infos}, {0: valid}, scene_errs,
                                                       [threshold], -1)
        return matches

    def recalls(self, case, matches):
        obj_ids = [p["id"] for p in case["parts"]]
        s = self.score.calc_localization_scores([0], obj_ids, matches, -1, do_print=False)
        return s["recall"], s["obj_recalls"], s["targets_count"]


def compare(case, ours, bop, stats):
    add_errors, mssd_errors, diameters, symmetric = {}, {}, {}, {}
    for part, vpart in zip(case["parts"], ours["parts"]):
        pts, diameter, syms, sym = bop.part_info(part)
        diameters[part["id"]], symmetric[part["id"]] = diameter, sym
        stats.diff("diameter", vpart["diameter"], diameter)
        for e, g, add, adds, mssd in vpart["pairs"]:
            b_add, b_adi, b_mssd = bop.pair_errors(pts, syms, case["estimates"][e][1], case["truth"][g][1])
            stats.diff("ADD", add, b_add)
            stats.diff("ADD-S", adds, b_adi)
            stats.diff("MSSD", mssd, b_mssd)
            add_errors[(e, g)] = b_adi if sym else b_add
            mssd_errors[(e, g)] = b_mssd
            # The other direction (estimate's vertices to the truth's), to show what it would change.
            old = bop.pose_error.adi(case["truth"][g][1][:3, :3], case["truth"][g][1][:3, 3:],
                                     case["estimates"][e][1][:3, :3], case["estimates"][e][1][:3, 3:], pts)
            if max(old, b_adi) < 0.2 * diameter:
                stats.gap = max(stats.gap, abs(old - b_adi) / diameter)
                stats.gap_mm = max(stats.gap_mm, abs(old - b_adi) * 1000)
            th = case["options"]["add_threshold"]
            stats.flips += (old / diameter < th) != (b_adi / diameter < th)
        stats.flag("uses_add_s", vpart["uses_add_s"] == sym)

    th = case["options"]["add_threshold"]
    add_matches = bop.match(case, add_errors, diameters, th)
    recall, obj_recalls, targets = bop.recalls(case, add_matches)
    by_truth = {m["gt_id"]: m["est_id"] for m in add_matches}
    for part, vpart in zip(case["parts"], ours["parts"]):
        for g, e, add, mssd in vpart["matches"]:
            theirs = by_truth.get(g, -2)
            on_knife = any(knife(add_errors.get((k, g)), diameters[part["id"]], th) for k in (e, theirs))
            stats.flag("ADD(-S) match", theirs == e, on_knife)
            if e >= 0:
                stats.diff("matched ADD(-S)", add, add_errors[(e, g)])
                stats.diff("matched MSSD", mssd, mssd_errors[(e, g)])
        if vpart["add_recall"] is not None:
            stats.diff("ADD(-S) recall per part", vpart["add_recall"], obj_recalls[part["id"]])
    if targets:
        stats.diff("ADD(-S) recall pooled", ours["add_recall"], recall)

    thresholds = np.arange(0.05, 0.51, 0.05)
    stats.diff("MSSD thresholds", max(abs(a - b) for a, b in zip(ours["mssd_thresholds"], thresholds)), 0)
    pooled, per_part = [], {p["id"]: [] for p in case["parts"]}
    for k, t in enumerate(thresholds):
        r, obj, _ = bop.recalls(case, bop.match(case, mssd_errors, diameters, t))
        pooled.append(r)
        for part, vpart in zip(case["parts"], ours["parts"]):
            per_part[part["id"]].append(obj[part["id"]])
            if vpart["mssd_recalls"]:
                stats.diff("MSSD recall per part and threshold", vpart["mssd_recalls"][k], obj[part["id"]])
    for part, vpart in zip(case["parts"], ours["parts"]):
        if vpart["mssd_average_recall"] is not None:
            stats.diff("MSSD average recall per part", vpart["mssd_average_recall"], np.mean(per_part[part["id"]]))
    if targets:
        stats.diff("MSSD average recall pooled", ours["mssd_average_recall"], float(np.mean(pooled)))


def knife(error, diameter, th):
    """True when the error is within 1e-9 of the threshold: a decision rounding may flip."""
    return error is not None and abs(error / diameter - th) < 1e-9


class Stats:
    def __init__(self):
        self.max = {}
        self.count = {}
        self.failed = {}
        self.knife = 0
        self.gap = 0.0  # largest |ADD-S one way - the other| / diameter, where both are below 0.2 diameters
        self.gap_mm = 0.0
        self.flips = 0  # pairs whose ADD-S decision at the case's threshold depends on the direction

    def diff(self, name, ours, theirs):
        d = abs(float(ours) - float(theirs))
        self.max[name] = max(self.max.get(name, 0.0), d)
        self.count[name] = self.count.get(name, 0) + 1

    def flag(self, name, same, on_knife=False):
        self.count[name] = self.count.get(name, 0) + 1
        if not same:
            if on_knife:
                self.knife += 1
            else:
                self.failed[name] = self.failed.get(name, 0) + 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=300)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--binary", default="build/release/bench/bop_score_cases")
    parser.add_argument("--toolkit", default=TOOLKIT)
    args = parser.parse_args()

    bop = Bop(load_toolkit(args.toolkit))
    rng = np.random.default_rng(args.seed)
    cases = [make_case(rng, i) for i in range(args.cases)]
    text = f"{len(cases)}\n" + "\n".join(case_text(c) for c in cases) + "\n"
    start = time.perf_counter()
    run = subprocess.run([args.binary], input=text, capture_output=True, text=True, check=True)
    vscan_s = time.perf_counter() - start
    lines = run.stdout.splitlines()
    assert len(lines) == len(cases), run.stderr

    stats = Stats()
    start = time.perf_counter()
    for case, line in zip(cases, lines):
        ours = json.loads(line)
        if "error" in ours:
            raise SystemExit(f"vscan refused a case: {ours['error']}")
        compare(case, ours, bop, stats)
    bop_s = time.perf_counter() - start

    kinds = {}
    for c in cases:
        for p in c["parts"]:
            kinds[p["kind"]] = kinds.get(p["kind"], 0) + 1
    pairs = stats.count.get("ADD", 0)
    print(f"{len(cases)} cases (seed {args.seed}), parts {kinds}, {pairs} estimate-truth pairs, "
          f"{stats.count.get('ADD(-S) match', 0)} valid true instances")
    print(f"{'quantity':40s} {'compared':>9s} {'max |vscan - BOP|':>18s}")
    for name in stats.max:
        print(f"{name:40s} {stats.count[name]:9d} {stats.max[name]:18.3g}")
    for name in ("uses_add_s", "ADD(-S) match"):
        print(f"{name + ' disagreements':40s} {stats.count.get(name, 0):9d} {stats.failed.get(name, 0):18d}")
    print(f"decisions within 1e-9 of a threshold that differ: {stats.knife}")
    print(f"ADD-S the other way round (estimate's vertices to the truth's) against adi, pairs with both under 0.2 "
          f"diameters: up to {stats.gap * 100:.2f}% of the diameter ({stats.gap_mm:.2f} mm); "
          f"{stats.flips} of {pairs} pairs change their decision at the case's threshold")
    print(f"vscan (bop_score_cases, incl. parsing) {vscan_s:.2f} s; bop_toolkit_lib {bop_s:.2f} s")
    bad = sum(stats.failed.values()) + sum(1 for n, v in stats.max.items() if v > 1e-9)
    print("RESULT:", "agree" if bad == 0 else "DISAGREE")
    return 0 if bad == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
