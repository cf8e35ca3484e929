#!/usr/bin/python3
"""Writes a copy of an ASL sequence (e.g. EuRoC) as an auto-exposure camera would have seen it.

Each frame's radiance (the original grey level, taken as linear) is multiplied by an exposure factor e(t), turned
into electrons (full-well capacity at grey 255), given photon shot noise (Poisson) and read noise, quantized to
8 bits and clipped. Profiles of e(t):

  hunting   exposure oscillating log-symmetrically between --lo and --hi with period --period [s] (default
            0.4x-2.5x, 0.8 s), phase jittered per --seed: an auto-exposure controller that hunts
  steps     exposure jumping between --lo and --hi every --period seconds: a controller with no smoothing
  dim       constant exposure --lo (a dim image: the same noise in electrons, amplified); with --gain G the
            camera's analog gain multiplies the electrons and the read noise (a dim room at high gain:
            --lo 0.008 --gain 128 --read-noise 0.5 gives EuRoC at an estimated SNR of about 5)

  scripts/exposure_stress.py DIR OUT [--profile hunting|steps|dim] [--frames N] [--lo 0.4] [--hi 2.5]
                             [--period 0.8] [--full-well 5000] [--read-noise 2.0] [--gain 1] [--seed 0]

DIR: ASL folder (DIR/mav0/cam0/data.csv + data/), OUT: the same layout (cam0 only, sensor.yaml copied,
groundtruth/ linked) plus OUT/events.csv (frame, timestamp, exposure factor). Frames are the first N of DIR.
"""
import argparse
import csv
import math
import os
import shutil
import sys

import cv2
import numpy as np


def exposure_factor(profile, t, lo, hi, period, phase):
    if profile == "dim":
        return lo
    if profile == "steps":
        return hi if int(math.floor(t / period + phase)) % 2 == 0 else lo
    mid, amp = 0.5 * (math.log(hi) + math.log(lo)), 0.5 * (math.log(hi) - math.log(lo))
    return math.exp(mid + amp * math.sin(2.0 * math.pi * (t / period + phase)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("src")
    ap.add_argument("out")
    ap.add_argument("--profile", choices=["hunting", "steps", "dim"], default="hunting")
    ap.add_argument("--frames", type=int, default=306)
    ap.add_argument("--lo", type=float, default=0.4)
    ap.add_argument("--hi", type=float, default=2.5)
    ap.add_argument("--period", type=float, default=0.8)
    ap.add_argument("--full-well", type=float, default=5000.0, help="electrons at grey 255 at exposure 1")
    ap.add_argument("--read-noise", type=float, default=2.0, help="read noise [grey levels at exposure 1]")
    ap.add_argument("--gain", type=float, default=1.0, help="analog gain after the read noise (every profile)")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    if not (a.lo > 0 and a.hi > 0 and a.period > 0 and a.full_well > 0 and a.read_noise >= 0 and a.frames > 0
            and a.gain > 0):
        sys.exit("exposure_stress.py: --lo, --hi, --period, --full-well, --frames, --gain must be > 0, --read-noise >= 0")
    cam = os.path.join(a.src, "mav0", "cam0")
    rows = []
    try:
        with open(os.path.join(cam, "data.csv")) as f:
            for r in csv.reader(f):
                if r and not r[0].startswith("#"):
                    rows.append((int(r[0]), r[1].strip()))
    except OSError as e:
        sys.exit("exposure_stress.py: %s: not an ASL sequence (%s)" % (a.src, e))
    rows = rows[: a.frames]
    out_cam = os.path.join(a.out, "mav0", "cam0")
    os.makedirs(os.path.join(out_cam, "data"), exist_ok=True)
    if os.path.exists(os.path.join(cam, "sensor.yaml")):
        shutil.copy(os.path.join(cam, "sensor.yaml"), out_cam)
    gt = os.path.join(a.src, "groundtruth")
    if os.path.isdir(gt) and not os.path.exists(os.path.join(a.out, "groundtruth")):
        os.symlink(os.path.abspath(gt), os.path.join(a.out, "groundtruth"))
    rng = np.random.default_rng(a.seed)
    phase = rng.uniform(0.0, 1.0)
    e_per_grey = a.full_well / 255.0
    t0 = rows[0][0] if rows else 0
    with open(os.path.join(out_cam, "data.csv"), "w") as f_csv, open(os.path.join(a.out, "events.csv"), "w") as f_ev:
        f_csv.write("#timestamp [ns],filename\n")
        f_ev.write("frame,timestamp_ns,exposure\n")
        for i, (stamp, name) in enumerate(rows):
            img = cv2.imread(os.path.join(cam, "data", name), cv2.IMREAD_GRAYSCALE)
            if img is None:
                print("exposure_stress.py: unreadable %s, skipped" % name, file=sys.stderr)
                continue
            e = exposure_factor(a.profile, (stamp - t0) * 1e-9, a.lo, a.hi, a.period, phase)
            electrons = rng.poisson(img.astype(np.float64) * e * e_per_grey)
            grey = (electrons / e_per_grey + rng.normal(0.0, a.read_noise, img.shape)) * a.gain
            out = np.clip(np.rint(grey), 0, 255).astype(np.uint8)
            cv2.imwrite(os.path.join(out_cam, "data", name), out)
            f_csv.write("%d,%s\n" % (stamp, name))
            f_ev.write("%d,%d,%.4f\n" % (i, stamp, e))
    print("exposure_stress.py: %s: %d frames to %s" % (a.profile, len(rows), a.out))


if __name__ == "__main__":
    main()
