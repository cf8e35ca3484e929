#!/usr/bin/python3
"""Noise vs mean grey of real and simulated cameras, fitted with the sensor model var = k * mean + floor.

  noise_model_check.py --asl DIR [--first 306 --last 599]   still frames of an ASL sequence: per-pixel
                                                          temporal mean and variance over the frames
  noise_model_check.py --stills DIR                       single photos: std of the flattest 8x8 blocks
                                                          per grey level (an upper bound of the noise)
Several --asl / --stills may be given. Prints per-level tables and the fit: k (DN per electron at the
camera's gain; full well = 255 / k if the ADC saturates at full well) and the read-noise floor in DN.
"""
import argparse
import glob
import os
import sys

import cv2
import numpy as np

BIN = 8  # grey levels per bin


def fit(levels, variances, weights):
    """Weighted least squares of var = k * level + floor."""
    a = np.stack([levels, np.ones_like(levels)], axis=1) * np.sqrt(weights)[:, None]
    (k, floor), *_ = np.linalg.lstsq(a, variances * np.sqrt(weights), rcond=None)
    return k, floor


def asl_frames(root, first, last):
    rows = []
    with open(os.path.join(root, "mav0/cam0/data.csv")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            rows.append(line.strip().split(",")[1].strip())
    return [os.path.join(root, "mav0/cam0/data", r) for r in rows[first:last + 1]]


def temporal(paths):
    """Per-pixel temporal mean / variance -> (level, var, count) per bin. Each frame is scaled to the
    median frame mean first: an exposure step of the camera is not noise."""
    imgs = [cv2.imread(p, cv2.IMREAD_GRAYSCALE).astype(np.float64) for p in paths]
    means = [img.mean() for img in imgs]
    ref = float(np.median(means))
    s = np.zeros_like(imgs[0])
    s2 = np.zeros_like(imgs[0])
    for img, m in zip(imgs, means):
        img = img * (ref / m)
        s += img
        s2 += img * img
    n = len(paths)
    mean = s / n
    var = (s2 - n * mean * mean) / (n - 1)
    # A still camera: the image must not move. Edges (where a sub-pixel shake shows) are left out.
    grad = cv2.magnitude(cv2.Sobel(mean, cv2.CV_64F, 1, 0), cv2.Sobel(mean, cv2.CV_64F, 0, 1))
    flat = grad < np.percentile(grad, 50)
    m = np.array(means)
    out = []
    for lo in range(0, 256, BIN):
        sel = flat & (mean >= lo) & (mean < lo + BIN)
        c = int(sel.sum())
        if c < 200:
            continue
        lvl = float(mean[sel].mean())
        out.append((lvl, float(np.median(var[sel])), c))
    return out, m


def stills(root):
    """Flattest 8x8 blocks per grey level over all photos: 10th percentile of the block variance."""
    per_bin = {}
    files = sorted(glob.glob(os.path.join(root, "*")))
    for p in files:
        img = cv2.imread(p, cv2.IMREAD_GRAYSCALE)
        if img is None:
            continue
        img = img.astype(np.float64)
        h, w = (img.shape[0] // 8) * 8, (img.shape[1] // 8) * 8
        blocks = img[:h, :w].reshape(h // 8, 8, w // 8, 8).transpose(0, 2, 1, 3).reshape(-1, 64)
        # Remove a plane per block (smooth shading is not noise).
        yy, xx = np.mgrid[0:8, 0:8]
        a = np.stack([xx.ravel(), yy.ravel(), np.ones(64)], axis=1)
        coef, *_ = np.linalg.lstsq(a, blocks.T, rcond=None)
        resid = blocks - (a @ coef).T
        bv = resid.var(axis=1) * 64 / 61
        bm = blocks.mean(axis=1)
        for lo in range(0, 256, BIN):
            sel = (bm >= lo) & (bm < lo + BIN) & (blocks.max(axis=1) < 250)
            if sel.any():
                per_bin.setdefault(lo, ([], []))
                per_bin[lo][0].extend(bm[sel])
                per_bin[lo][1].extend(bv[sel])
    out = []
    for lo in sorted(per_bin):
        m, v = per_bin[lo]
        if len(v) < 50:
            continue
        out.append((float(np.mean(m)), float(np.percentile(v, 10)), len(v)))
    return out, len(files)


def report(name, rows, max_level=230):
    rows = [r for r in rows if r[0] < max_level]
    print(f"\n{name}\n  level   std(DN)  var(DN^2)  pixels/blocks")
    for lvl, var, c in rows:
        print(f"  {lvl:6.1f}  {np.sqrt(max(var, 0.0)):7.3f}  {var:9.3f}  {c}")
    if len(rows) < 3:
        print("  (too few levels to fit)")
        return None
    lv = np.array([r[0] for r in rows])
    vv = np.array([r[1] for r in rows])
    w = np.sqrt(np.array([r[2] for r in rows], dtype=float))
    k, floor = fit(lv, vv, w)
    rms = np.sqrt(np.mean((k * lv + floor - vv) ** 2))
    print(f"  fit: var = {k:.4f} * level + {floor:.3f}  (k = {k:.4f} DN/e-, full well 255/k = "
          f"{255 / k if k > 0 else float('inf'):.0f} e-, floor std {np.sqrt(max(floor, 0)):.2f} DN, "
          f"fit rms {rms:.3f} DN^2)")
    return k, floor


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--asl", action="append", default=[])
    ap.add_argument("--stills", action="append", default=[])
    ap.add_argument("--first", type=int, default=306)
    ap.add_argument("--last", type=int, default=599)
    args = ap.parse_args()
    if not args.asl and not args.stills:
        ap.error("give --asl DIR and/or --stills DIR")
    for root in args.asl:
        if not os.path.isfile(os.path.join(root, "mav0/cam0/data.csv")):
            sys.exit(f"{root}: not an ASL sequence (no mav0/cam0/data.csv)")
        paths = asl_frames(root, args.first, args.last)
        if len(paths) < 10:
            sys.exit(f"{root}: only {len(paths)} frames in [{args.first}, {args.last}]")
        rows, means = temporal(paths)
        print(f"\n{root}: frames {args.first}-{args.first + len(paths) - 1} ({len(paths)}), frame mean "
              f"{means.mean():.2f} +- {means.std():.3f} DN")
        report("temporal noise per level (flat half of the pixels)", rows)
    for root in args.stills:
        rows, n = stills(root)
        report(f"{root}: {n} photos, flattest 8x8 blocks (10th percentile of the block variance)", rows)


if __name__ == "__main__":
    main()
