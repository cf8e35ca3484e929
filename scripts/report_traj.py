#!/usr/bin/python3
"""Trajectory figures of scripts/report.py (paper Figs. 6-8) and the per-mode styles they share.

Every mode is drawn in its own colour, line style and marker (staggered markers, wide translucent lines below,
thin dashed ones on top), so overlapping trajectories stay visible. The APE-over-time plot (Fig. 8) shades the
photometric events of the sequence's events.csv (iraf_vo_simulate / iraf_vo_degrade). Imported by report.py.
"""
import math
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
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


def fmt_len(v):
    """A length in m as mm below 0.1 m (trajectory errors of a few mm stay readable)."""
    if v is None or not math.isfinite(v):
        return "-"
    return "%.1f mm" % (1000 * v) if abs(v) < 0.1 else "%.3f m" % v


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
