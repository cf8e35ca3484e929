#!/usr/bin/env python3
"""Table of the simulator scenarios run by scripts/reproduce.sh (OUT/scenarios.csv): per sequence and mode the
camera, the first frame of motion (from the ground truth: the first pose that differs from frame 0), the first
frame with a pose (initialization), tracked % over the frames after the first 5 frames of motion, lost events,
Sim(3) ATE RMSE, the ground-truth path length and the ATE in % of it. pass = tracked >= 95 % and ATE <= 1 %
of the path. Writes OUT/scenarios.md and OUT/scenarios_table.csv.

    scripts/sim_scenarios.py --out /tmp/iraf_vo_report
"""
import argparse
import csv
import math
import os
import sys


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from report import die, load_json  # noqa: E402  (scripts/report.py: same error handling)


def read_gt(path):
    """TUM rows (t, x, y, z, qx, qy, qz, qw)."""
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            v = [float(x) for x in line.split()]
            if len(v) != 8:
                die("%s: bad TUM row '%s'" % (path, line))
            rows.append(v)
    if len(rows) < 2:
        die("%s: fewer than 2 poses" % path)
    return rows


def motion_start(gt):
    """Index of the first pose that differs from pose 0 (0 when the camera moves from the start)."""
    for i, r in enumerate(gt):
        if any(abs(a - b) > 1e-9 for a, b in zip(r[1:], gt[0][1:])):
            return max(0, i - 1)
    return len(gt)


def path_length(gt):
    return sum(math.dist(a[1:4], b[1:4]) for a, b in zip(gt, gt[1:]))


def frame_states(path):
    with open(path) as f:
        return [r["state"] for r in csv.DictReader(f)]


def camera_of(asl):
    p = os.path.join(asl, "mav0", "cam0", "sensor.yaml")
    if not os.path.isfile(p):
        return "?"
    res, model = "", ""
    with open(p) as f:
        for line in f:
            if line.startswith("resolution:"):
                res = line.split(":", 1)[1].strip().strip("[]").replace(", ", "x")
            if line.startswith("distortion_model:"):
                model = "fisheye" if "equidistant" in line else "pinhole"
    return "%s %s" % (model, res)


def scenario_row(r, st, ev):
    """One table row from an index row, its iraf_vo_run stats and iraf_vo_eval json."""
    gt = read_gt(r["gt"])
    start = motion_start(gt)
    flog = r["traj"][:-len(".txt")] + ".frames.csv"
    tracked = [s == "tracking" for s in frame_states(flog)] if os.path.isfile(flog) else []
    after = tracked[start + 5:]
    ate = (ev or {}).get("ate", {}).get("rmse", st.get("ate_rmse"))
    length = path_length(gt)
    row = {
        "sequence": r["sequence"], "mode": r["mode"], "camera": camera_of(r["path"]),
        "frames": len(tracked) or st.get("frames"), "motion_start": start,
        "first_init": next((i for i, t in enumerate(tracked) if t), None),
        "static_tracked": sum(tracked[:start + 1]) if start > 0 else None,
        "tracked_after_pct": 100.0 * sum(after) / len(after) if after else None,
        "lost_events": st.get("lost_events"), "resets": st.get("resets"), "ate_rmse": ate,
        "path_m": length, "ate_pct": 100.0 * ate / length if ate is not None and length > 0 else None,
    }
    row["pass"] = (row["tracked_after_pct"] is not None and row["tracked_after_pct"] >= 95.0
                   and row["ate_pct"] is not None and row["ate_pct"] <= 1.0)
    return row


def collect(out):
    path = os.path.join(out, "scenarios.csv")
    if not os.path.isfile(path):
        die("%s missing: run scripts/reproduce.sh first" % path)
    with open(path) as f:
        runs = [(r, load_json(r["stats"])) for r in csv.DictReader(f)]
    rows = [scenario_row(r, st, load_json(r["eval_json"])) for r, st in runs if st is not None]
    if not rows:
        die("no finished scenario run in %s" % path)
    return rows


def fmt(v, spec):
    return "-" if v is None else spec % v


def markdown(rows):
    lines = ["## Simulator scenarios (other cameras and motions)\n",
             "tracked % = frames with a pose among the frames after the first 5 frames of motion; init = first frame "
             "with a pose; static tracked = frames with a pose while the camera stood still (should be 0: no "
             "initialization without motion); ATE = Sim(3) RMSE over the tracked frames; % path = ATE / length of the "
             "ground-truth path. pass = tracked >= 95 % and ATE <= 1 % of the path.\n",
             "| sequence | mode | camera | frames | motion from | init | static tracked | tracked % | lost | "
             "ATE RMSE [m] | path [m] | ATE % path | pass |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        lines.append("| %s | %s | %s | %s | %d | %s | %s | %s | %s | %s | %.2f | %s | %s |" % (
            r["sequence"], r["mode"], r["camera"], r["frames"], r["motion_start"], fmt(r["first_init"], "%d"),
            fmt(r["static_tracked"], "%d"), fmt(r["tracked_after_pct"], "%.1f"), fmt(r["lost_events"], "%d"),
            fmt(r["ate_rmse"], "%.4f"), r["path_m"], fmt(r["ate_pct"], "%.2f"), "yes" if r["pass"] else "**no**"))
    n_pass = sum(r["pass"] for r in rows)
    lines.append("\n%d of %d scenario runs pass.\n" % (n_pass, len(rows)))
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="/tmp/iraf_vo_report")
    a = ap.parse_args()
    rows = collect(a.out)
    cols = list(rows[0].keys())
    with open(os.path.join(a.out, "scenarios_table.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)
    md = markdown(rows)
    with open(os.path.join(a.out, "scenarios.md"), "w") as f:
        f.write(md)
    print(md)


if __name__ == "__main__":
    main()
