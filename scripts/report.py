#!/usr/bin/python3
"""Ablation table + paper figures from the runs of scripts/reproduce.sh.

    scripts/report.py --out DIR          # reads DIR/index.csv (+ runs/, keypoint_curve.csv, settings.txt),
                                         # writes DIR/report.md, DIR/results.csv and DIR/fig*.png
    scripts/report.py --darkest ASL_DIR [--max-frames N]   # prints the path of the darkest frame (for Fig. 4)

Only numpy, matplotlib (Agg) and yaml.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

MODES = ["baseline", "he", "clahe", "enhance", "adaptive", "culling", "iraf"]
MODE_LABEL = {
    "baseline": "ORB-SLAM baseline",
    "he": "HE",
    "clahe": "CLAHE",
    "enhance": "+enhance",
    "adaptive": "+adaptive threshold",
    "culling": "+culling",
    "iraf": "IRAF (full)",
}
# Line style, marker and width per mode: overlapping trajectories stay distinguishable (every mode is drawn;
# the wide translucent lines go below, the thin dashed ones on top).
MODE_STYLE = {
    "baseline": dict(ls="-", marker="o", lw=2.6, alpha=0.75, zorder=3),
    "he": dict(ls="--", marker="v", lw=1.3, alpha=0.9, zorder=5),
    "clahe": dict(ls="-.", marker="^", lw=1.3, alpha=0.9, zorder=5),
    "enhance": dict(ls=(0, (5, 2, 1, 2)), marker="s", lw=1.3, alpha=0.9, zorder=6),
    "adaptive": dict(ls=":", marker="D", lw=1.6, alpha=0.9, zorder=6),
    "culling": dict(ls=(0, (1, 1)), marker="P", lw=1.6, alpha=0.9, zorder=6),
    "iraf": dict(ls="-", marker="x", lw=1.4, alpha=0.95, zorder=7),
}
EVENT_COLOR = {"gain_ramp": "#555555", "over_exposure": "#f5b700", "light_switch": "#17becf", "flicker": "#1f9e89",
               "spotlight": "#ff9896", "shadow": "#7f7f7f", "vignetting": "#c5b0d5", "noise": "#bcbd22",
               "motion_blur": "#8c6d31"}

MODE_COLOR = {
    "baseline": "#1f77b4",
    "he": "#9467bd",
    "clahe": "#8c564b",
    "enhance": "#ff7f0e",
    "adaptive": "#2ca02c",
    "culling": "#e377c2",
    "iraf": "#d62728",
}


def die(msg):
    sys.stderr.write("report.py: %s\n" % msg)
    sys.exit(1)


def load_json(path):
    if not path or not os.path.isfile(path):
        return None
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.stderr.write("report.py: %s: %s (ignored)\n" % (path, e))
        return None


def load_errors(path):
    """t,error,est_x,est_y,est_z,gt_x,gt_y,gt_z of iraf_vo_eval --csv -> dict of arrays (or None)."""
    if not path or not os.path.isfile(path):
        return None
    try:
        a = np.genfromtxt(path, delimiter=",", names=True, comments="#")
    except (OSError, ValueError) as e:
        sys.stderr.write("report.py: %s: %s (ignored)\n" % (path, e))
        return None
    if a.size == 0:
        return None
    a = np.atleast_1d(a)
    need = ["t", "error", "est_x", "est_y", "est_z", "gt_x", "gt_y", "gt_z"]
    if any(n not in a.dtype.names for n in need):
        sys.stderr.write("report.py: %s: expected columns %s (ignored)\n" % (path, ",".join(need)))
        return None
    return {n: np.asarray(a[n], dtype=float) for n in need}


def darkest(asl_dir, max_frames):
    """Path of the darkest of every 5th frame among the first max_frames of an ASL folder."""
    csv_path = os.path.join(asl_dir, "mav0", "cam0", "data.csv")
    if not os.path.isfile(csv_path):
        die("%s: no mav0/cam0/data.csv" % asl_dir)
    names = []
    with open(csv_path) as f:
        for row in csv.reader(f):
            if not row or row[0].startswith("#"):
                continue
            names.append(row[1].strip())
    names = names[:max_frames] if max_frames > 0 else names
    best, best_mean = None, 1e9
    for n in names[::5]:
        p = os.path.join(asl_dir, "mav0", "cam0", "data", n)
        try:
            im = mpimg.imread(p)
        except (OSError, ValueError, SyntaxError):
            continue
        m = float(np.mean(im))
        if m < best_mean:
            best, best_mean = p, m
    if best is None:
        die("%s: no readable frame" % asl_dir)
    print(best)


def fmt_len(v):
    """A length in m as mm below 0.1 m (trajectory errors of a few mm stay readable)."""
    if v is None or not math.isfinite(v):
        return "-"
    return "%.1f mm" % (1000 * v) if abs(v) < 0.1 else "%.3f m" % v


def fmt(v, spec, missing="-"):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return missing
    return spec % v


def collect(out):
    index = os.path.join(out, "index.csv")
    if not os.path.isfile(index):
        die("%s missing: run scripts/reproduce.sh first" % index)
    rows = []
    with open(index) as f:
        for r in csv.DictReader(f):
            st = load_json(r["stats"])
            if st is None:
                continue
            ev = load_json(r["eval_json"])
            ate = ev.get("ate", {}) if ev else {}
            row = {
                "sequence": r["sequence"],
                "mode": r["mode"],
                "frames": st.get("frames"),
                "tracked_pct": st.get("tracked_pct"),
                "lost_events": st.get("lost_events"),
                "resets": st.get("resets"),
                "keyframes": st.get("keyframes"),
                "ate_rmse": ate.get("rmse", st.get("ate_rmse")),
                "ate_mean": ate.get("mean"),
                "ate_max": ate.get("max"),
                "coverage": ev.get("coverage") if ev else None,
                "cpu_ms_per_frame": st.get("cpu_ms_per_frame"),
                "ms_features": st.get("ms", {}).get("features", {}).get("mean"),
                "ms_enhance": st.get("ms", {}).get("enhance", {}).get("mean"),
                "ms_track": st.get("ms", {}).get("track", {}).get("mean"),
                "wall_s": float(r["wall_s"]) if r["wall_s"] else None,
                "errors_csv": r["errors_csv"],
                "path": r.get("path", ""),
                "traj": r["traj"],
            }
            row["wall_ms_per_frame"] = (1000.0 * row["wall_s"] / row["frames"]
                                        if row["wall_s"] and row["frames"] else None)
            rows.append(row)
    if not rows:
        die("no finished run in %s" % index)
    return rows


def write_csv(rows, path):
    cols = ["sequence", "mode", "frames", "tracked_pct", "lost_events", "resets", "keyframes", "ate_rmse",
            "ate_mean", "ate_max", "coverage", "cpu_ms_per_frame", "wall_ms_per_frame", "ms_enhance",
            "ms_features", "ms_track"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow(["" if r[c] is None else (("%.6g" % r[c]) if isinstance(r[c], float) else r[c])
                        for c in cols])


def ordered_sequences(rows):
    seen = []
    for r in rows:
        if r["sequence"] not in seen:
            seen.append(r["sequence"])
    return seen


def markdown(rows, settings, figures):
    seqs = ordered_sequences(rows)
    lines = []
    mapping = settings.get("mapping", "?")
    lines.append("# iraf_vo evidence: ablation and figures\n")
    lines.append("Settings: " + "; ".join("%s: %s" % kv for kv in settings.items()) + "\n")
    lines.append(
        "Table: every sequence x front-end mode through the same `iraf_vo_run` tracking code. "
        "Mapping %s. tracked %% = frames with a pose / all frames (the first frames before the two-view "
        "initialization count as untracked); lost = tracking-loss events; ATE = Sim(3)-aligned absolute "
        "trajectory error over the tracked frames (`iraf_vo_eval --align sim3`), RMSE and mean; ms/frame = "
        "CPU time of the whole process (all threads: PNG decoding, enhancement, features, tracking, BA) per frame. "
        "**Bold** = lowest ATE RMSE of the sequence among runs tracking >= 90 %% of the best tracked %%.\n"
        % mapping)
    lines.append("| sequence | mode | tracked % | lost | resets | ATE RMSE [m] | ATE mean [m] | CPU ms/frame |")
    lines.append("|---|---|---:|---:|---:|---:|---:|---:|")
    for s in seqs:
        rs = [r for r in rows if r["sequence"] == s]
        rs.sort(key=lambda r: MODES.index(r["mode"]) if r["mode"] in MODES else 99)
        best_tr = max((r["tracked_pct"] or 0) for r in rs)
        cand = [r for r in rs if r["ate_rmse"] is not None and (r["tracked_pct"] or 0) >= 0.9 * best_tr]
        best = min(cand, key=lambda r: r["ate_rmse"]) if cand else None
        for r in rs:
            ate = fmt(r["ate_rmse"], "%.4f")
            if r is best:
                ate = "**%s**" % ate
            lines.append("| %s | %s | %s | %s | %s | %s | %s | %s |" % (
                s, r["mode"], fmt(r["tracked_pct"], "%.1f"), fmt(r["lost_events"], "%d"), fmt(r["resets"], "%d"),
                ate, fmt(r["ate_mean"], "%.4f"), fmt(r["cpu_ms_per_frame"], "%.1f")))
    # Per-mode summary (Table II style).
    lines.append("")
    lines.append("Summary per mode over the %d sequences: mean tracked %%, total lost events, median of the "
                 "per-sequence ATE RMSE, number of sequences where the mode has the lowest ATE RMSE (bold above), "
                 "mean CPU ms/frame.\n" % len(seqs))
    lines.append("| mode | mean tracked % | lost events | median ATE RMSE [m] | best ATE on | CPU ms/frame |")
    lines.append("|---|---:|---:|---:|---:|---:|")
    wins = {}
    for s in seqs:
        rs = [r for r in rows if r["sequence"] == s]
        best_tr = max((r["tracked_pct"] or 0) for r in rs)
        cand = [r for r in rs if r["ate_rmse"] is not None and (r["tracked_pct"] or 0) >= 0.9 * best_tr]
        if cand:
            b = min(cand, key=lambda r: r["ate_rmse"])
            wins[b["mode"]] = wins.get(b["mode"], 0) + 1
    for m in MODES:
        rs = [r for r in rows if r["mode"] == m]
        if not rs:
            continue
        tr = [r["tracked_pct"] for r in rs if r["tracked_pct"] is not None]
        lost = sum(r["lost_events"] or 0 for r in rs)
        ate = [r["ate_rmse"] for r in rs if r["ate_rmse"] is not None]
        ms = [r["cpu_ms_per_frame"] for r in rs if r["cpu_ms_per_frame"] is not None]
        lines.append("| %s | %s | %d | %s | %d | %s |" % (
            m, fmt(float(np.mean(tr)) if tr else None, "%.1f"), lost,
            fmt(float(np.median(ate)) if ate else None, "%.4f"), wins.get(m, 0),
            fmt(float(np.mean(ms)) if ms else None, "%.1f")))
    lines.append("")
    if figures:
        lines.append("Figures:\n")
        for name, desc in figures:
            lines.append("- `%s`: %s" % (name, desc))
        lines.append("")
    return "\n".join(lines) + "\n"


def fig3(out):
    path = os.path.join(out, "keypoint_curve.csv")
    if not os.path.isfile(path):
        print("report.py: %s missing: Fig. 3 skipped" % path)
        return None
    data = {}  # variant -> threshold -> list
    adaptive = {}
    gthr = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            v = r["variant"]
            if r["threshold"] == "adaptive":
                adaptive.setdefault(v, []).append(float(r["keypoints"]))
                if r["global_threshold"]:
                    gthr.setdefault(v, []).append(float(r["global_threshold"]))
            else:
                data.setdefault(v, {}).setdefault(int(r["threshold"]), []).append(float(r["keypoints"]))
    n_img = len(adaptive.get("original", []))
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    style = {"original": ("#1f77b4", "original"), "enhanced": ("#d62728", "enhanced (IRAF eqs. 1-12)")}
    for v in ["original", "enhanced"]:
        if v not in data:
            continue
        th = sorted(data[v])
        mean = [np.mean(data[v][t]) for t in th]
        col, lab = style[v]
        ax.plot(th, mean, "-o", color=col, label="%s, fixed FAST threshold" % lab, ms=4)
        if v in adaptive and v in gthr:
            gx, gy = float(np.mean(gthr[v])), float(np.mean(adaptive[v]))
            ax.plot([gx], [gy], marker="*", ms=16, color=col, mec="k", ls="none",
                    label="%s, adaptive (mean $F_t^g$ = %.1f, %.0f kps)" % (v, gx, gy))
            ax.axvline(gx, color=col, ls=":", lw=1)
    ax.axvline(20, color="0.4", ls="--", lw=1)
    ax.text(20.5, ax.get_ylim()[1] * 0.95, "ORB-SLAM default 20", color="0.3", fontsize=8, va="top")
    ax.set_yscale("log")
    ax.set_xlabel("FAST threshold")
    ax.set_ylabel("mean keypoints per image (log)")
    ax.set_title("Fig. 3: FAST keypoints vs threshold, %d low-light stills (DICM + LIME)" % n_img, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    name = "fig3_keypoint_curve.png"
    fig.savefig(os.path.join(out, name))
    plt.close(fig)
    return (name, "Fig. 3: mean FAST keypoint count vs fixed threshold on the %d low-light stills, original vs "
                  "enhanced (log scale); stars = the adaptive threshold's count at the mean global threshold "
                  "F_t^g (dotted lines)" % n_img)


def best_plane(gt_xyz):
    """The two axes with the largest ground-truth extent (top-down view of the most informative plane)."""
    ext = gt_xyz.max(axis=0) - gt_xyz.min(axis=0)
    a, b = sorted(np.argsort(ext)[::-1][:2])
    return a, b


def mode_line(ax, x, y, m, label=None, n_markers=14, scale=1.0):
    """One mode's curve in its MODE_STYLE (markers every len/n_markers points so the line stays readable)."""
    st = MODE_STYLE[m]
    step = max(1, len(x) // n_markers)
    offset = (MODES.index(m) * step) // len(MODES)  # staggered: the modes' markers do not sit on each other
    ax.plot(x, y, linestyle=st["ls"], marker=st["marker"], markevery=(offset, step), ms=4.5 * scale,
            lw=st["lw"] * scale, alpha=st["alpha"], zorder=st["zorder"], color=MODE_COLOR[m], mfc="none",
            mew=1.1, label=label)


def load_events(path):
    """Photometric events of a sequence folder: [(type, t_start, t_end)] in data.csv seconds, from
    PATH/events.csv (iraf_vo_simulate / iraf_vo_degrade: type,start_frame,end_frame,...; end -1 = to the end)
    and PATH/mav0/cam0/data.csv (frame -> stamp). [] when either is missing (real sequences, bags)."""
    ev_csv = os.path.join(path or "", "events.csv")
    data_csv = os.path.join(path or "", "mav0", "cam0", "data.csv")
    if not path or not os.path.isfile(ev_csv) or not os.path.isfile(data_csv):
        return []
    stamps = []
    with open(data_csv) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                try:
                    stamps.append(int(line.split(",")[0]) * 1e-9)
                except ValueError:
                    pass
    if not stamps:
        return []
    events = []
    with open(ev_csv) as f:
        for line in f:
            parts = [p.strip() for p in line.split(",")]
            if not line.strip() or line.lstrip().startswith("#") or len(parts) < 3:
                continue
            try:
                start, end = int(parts[1]), int(parts[2])
            except ValueError:
                continue
            if start >= len(stamps):
                continue
            end = len(stamps) - 1 if end < 0 or end >= len(stamps) else end
            events.append((parts[0], stamps[start], stamps[end]))
    return events


def mark_events(ax, events, t0, t_max):
    """Shaded span + dashed start line + label per photometric event inside [0, t_max] (time relative to t0).
    Events covering >= 90 % of the run (vignetting, noise) are listed in a corner note instead of shading it all."""
    whole = []
    for kind, ts, te in events:
        a, b = max(ts - t0, 0.0), min(te - t0, t_max)
        if b <= a:
            continue
        if t_max > 0 and b - a >= 0.9 * t_max:
            whole.append(kind)
            continue
        col = EVENT_COLOR.get(kind, "#2ca02c")
        ax.axvspan(a, b, color=col, alpha=0.18, zorder=0, lw=0)
        ax.axvline(a, color=col, lw=1.0, ls="--", alpha=0.8, zorder=1)
        # Vertical label at the event's start: neighbouring events do not overwrite each other.
        ax.text(a, 0.99, kind, transform=ax.get_xaxis_transform(), fontsize=7, va="top", ha="right",
                rotation=90, color="k", alpha=0.85, zorder=8)
    if whole:
        ax.text(0.995, 0.015, "whole run: " + ", ".join(sorted(set(whole))), transform=ax.transAxes, fontsize=7,
                ha="right", va="bottom", alpha=0.8)


def traj_figures(out, rows, seq):
    rs = {r["mode"]: r for r in rows if r["sequence"] == seq}
    errs = {m: load_errors(r["errors_csv"]) for m, r in rs.items()}
    errs = {m: e for m, e in errs.items() if e is not None and len(e["t"]) > 1}
    if "iraf" not in errs and "baseline" not in errs:
        return []
    figs = []
    t0 = min(float(e["t"][0]) for e in errs.values())
    # Ground truth at the matched stamps of the run with the most matches (all runs use the same GT).
    gt_run = max(errs.values(), key=lambda e: len(e["t"]))
    gt = np.stack([gt_run["gt_x"], gt_run["gt_y"], gt_run["gt_z"]], axis=1)
    axn = "xyz"
    a, b = best_plane(gt)
    show = [m for m in MODES if m in errs]  # every mode, in its own style

    def label(m):
        r = rs[m]
        return "%s (ATE %s, %.0f %% tracked)" % (MODE_LABEL[m], fmt_len(r["ate_rmse"]), r["tracked_pct"] or 0)

    # Fig. 6: top-down trajectory.
    fig, ax = plt.subplots(figsize=(6.5, 5.5), dpi=110)
    ax.plot(gt[:, a], gt[:, b], "-", color="k", lw=4.0, alpha=0.25, zorder=2, label="ground truth")
    for m in show:
        e = errs[m]
        est = np.stack([e["est_x"], e["est_y"], e["est_z"]], axis=1)
        mode_line(ax, est[:, a], est[:, b], m, label=label(m))
    ax.plot(gt[0, a], gt[0, b], "o", color="k", ms=6)
    ax.set_xlabel("%s [m]" % axn[a])
    ax.set_ylabel("%s [m]" % axn[b])
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title("Fig. 6: %s, %s-%s plane, Sim(3)-aligned (o = start)" % (seq, axn[a], axn[b]), fontsize=10)
    fig.tight_layout()
    name = "fig6_trajectory_%s.png" % seq
    fig.savefig(os.path.join(out, name))
    plt.close(fig)
    figs.append((name, "Fig. 6: %s top-down trajectory (%s-%s) of every mode vs ground truth, Sim(3)-aligned"
                 % (seq, axn[a], axn[b])))

    # Fig. 7: x / y / z over time.
    fig, axs = plt.subplots(3, 1, figsize=(7.5, 6.5), dpi=110, sharex=True)
    tg = gt_run["t"] - t0
    for k in range(3):
        axs[k].plot(tg, gt[:, k], "-", color="k", lw=4.0, alpha=0.25, zorder=2, label="ground truth")
        for m in show:
            e = errs[m]
            est = np.stack([e["est_x"], e["est_y"], e["est_z"]], axis=1)
            # Untracked frames leave gaps: break the line where consecutive matches are > 3 median steps apart.
            t = e["t"] - t0
            y = est[:, k].copy()
            if len(t) > 2:
                gap = np.diff(t) > 3 * np.median(np.diff(t))
                t = np.insert(t, np.nonzero(gap)[0] + 1, np.nan)
                y = np.insert(y, np.nonzero(gap)[0] + 1, np.nan)
            mode_line(axs[k], t, y, m, label=MODE_LABEL[m], n_markers=25, scale=0.8)
        axs[k].set_ylabel("%s [m]" % axn[k])
        axs[k].grid(True, alpha=0.3)
    axs[0].legend(fontsize=7, loc="best", ncol=2)
    axs[2].set_xlabel("time [s]")
    axs[0].set_title("Fig. 7: %s position over time (Sim(3)-aligned; gaps = untracked frames)" % seq, fontsize=10)
    fig.tight_layout()
    name = "fig7_xyz_%s.png" % seq
    fig.savefig(os.path.join(out, name))
    plt.close(fig)
    figs.append((name, "Fig. 7: %s x/y/z over time of every mode vs ground truth" % seq))

    # Fig. 8: APE over time, every mode, photometric events shaded. Log scale when the runs differ by more than 5x.
    fig, ax = plt.subplots(figsize=(7.5, 5.4), dpi=110)
    rmses = [rs[m]["ate_rmse"] for m in errs if rs[m]["ate_rmse"]]
    log_y = bool(rmses) and max(rmses) > 5 * min(rmses)
    ymax, ymin = 0.0, float("inf")
    for m in MODES:
        if m not in errs:
            continue
        e = errs[m]
        mode_line(ax, e["t"] - t0, e["error"], m, label="%s (RMSE %s)" % (MODE_LABEL[m], fmt_len(rs[m]["ate_rmse"])),
                  n_markers=20, scale=0.8)
        ymax = max(ymax, float(np.max(e["error"])))
        pos = e["error"][e["error"] > 0]
        if pos.size:
            ymin = min(ymin, float(np.percentile(pos, 2)))
    if log_y:
        ax.set_yscale("log")
        ax.set_ylim(max(ymin * 0.8, 1e-5), ymax * 3)
    else:
        ax.set_ylim(0, ymax * 1.35 if ymax > 0 else 1)
    events = load_events(rs[next(iter(errs))].get("path"))
    mark_events(ax, events, t0, max(float(e["t"][-1]) for e in errs.values()) - t0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("APE [m]" + (" (log)" if log_y else ""))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    ax.set_title("Fig. 8: %s absolute pose error over time (Sim(3)-aligned per run)" % seq, fontsize=10)
    fig.tight_layout()
    name = "fig8_ape_%s.png" % seq
    fig.savefig(os.path.join(out, name))
    plt.close(fig)
    figs.append((name, "Fig. 8: %s APE over time for every mode (log y axis when the modes' RMSE differ > 5x)%s"
                 % (seq, "; shaded: photometric events of events.csv" if events else "")))
    return figs


def read_settings(out):
    s = {}
    p = os.path.join(out, "settings.txt")
    if os.path.isfile(p):
        with open(p) as f:
            for line in f:
                if ":" in line:
                    k, v = line.split(":", 1)
                    s[k.strip()] = v.strip()
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="/tmp/iraf_vo_report")
    ap.add_argument("--darkest", metavar="ASL_DIR")
    ap.add_argument("--max-frames", type=int, default=0)
    ap.add_argument("--fig-sequences", default="",
                    help="comma-separated sequences for Figs. 6-8 (default: every sequence)")
    a = ap.parse_args()
    if a.darkest:
        darkest(a.darkest, a.max_frames)
        return
    if not os.path.isdir(a.out):
        die("--out %s: no such folder" % a.out)
    rows = collect(a.out)
    write_csv(rows, os.path.join(a.out, "results.csv"))
    figures = []
    f3 = fig3(a.out)
    if f3:
        figures.append(f3)
    for f4 in sorted(n for n in os.listdir(a.out) if n.startswith("fig4_keypoints_") and n.endswith(".png")):
        figures.append((f4, "Fig. 4: keypoints of our FeatureExtractor on the darkest frame of %s: left baseline "
                            "(original image, FAST 20/7, no culling), right IRAF (enhanced, adaptive threshold, kept "
                            "keypoints red->green by stability S, culled ones as magenta crosses)"
                        % f4[len("fig4_keypoints_"):-4]))
    seqs = ordered_sequences(rows)
    if a.fig_sequences:
        wanted = [s for s in a.fig_sequences.split(",") if s]
        seqs = [s for s in seqs if s in wanted]
    for s in seqs:
        figures += traj_figures(a.out, rows, s)
    md = markdown(rows, read_settings(a.out), figures)
    with open(os.path.join(a.out, "report.md"), "w") as f:
        f.write(md)
    print(md)


if __name__ == "__main__":
    main()
