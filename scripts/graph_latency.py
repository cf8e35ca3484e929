#!/usr/bin/env python3
"""Latency of the running nodelet graph: for every image on --image, the wall time until the odometry
with the same header stamp arrives on --odometry (both received by this node, so the number is the graph's
processing time plus two transport hops), and the peak resident memory (VmHWM) of the nodelet manager process.
Stops when no image arrived for --idle seconds after the first one. Prints a summary, exit 1 if nothing arrived.

    scripts/graph_latency.py [--image /cam0/image_raw] [--odometry /odometry] [--manager iraf_vo_manager] [--idle 5]
"""
import argparse
import os
import sys
import threading
import time

import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image


def manager_peak_rss_mib(name):
    """VmHWM of the process started with __name:=name (the nodelet manager), None if not found."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                args = f.read().split(b"\0")
            if ("__name:=" + name).encode() not in args:
                continue
            with open("/proc/%s/status" % pid) as f:
                for line in f:
                    if line.startswith("VmHWM:"):
                        return int(line.split()[1]) / 1024.0
        except OSError:
            continue
    return None


def percentile(values, q):
    s = sorted(values)
    return s[min(len(s) - 1, int(q * (len(s) - 1) + 0.5))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--image", default="/cam0/image_raw")
    ap.add_argument("--odometry", default="/odometry")
    ap.add_argument("--manager", default="iraf_vo_manager")
    ap.add_argument("--idle", type=float, default=5.0)
    ap.add_argument("--timeout", type=float, default=120.0, help="give up if no image arrives within this time")
    args = ap.parse_args(rospy.myargv()[1:])
    rospy.init_node("graph_latency", anonymous=True)
    lock = threading.Lock()
    image_wall = {}  # header stamp -> wall receive time
    latencies = []
    state = {"last_image": None, "odometry": 0}

    def on_image(msg):
        now = time.monotonic()
        with lock:
            image_wall[msg.header.stamp.to_nsec()] = now
            state["last_image"] = now

    def on_odometry(msg):
        now = time.monotonic()
        with lock:
            state["odometry"] += 1
            t = image_wall.pop(msg.header.stamp.to_nsec(), None)
            if t is not None:
                latencies.append(1000.0 * (now - t))

    rospy.Subscriber(args.image, Image, on_image, queue_size=100, buff_size=2 ** 24)
    rospy.Subscriber(args.odometry, Odometry, on_odometry, queue_size=100)
    start = time.monotonic()
    while not rospy.is_shutdown():
        time.sleep(0.2)
        with lock:
            last = state["last_image"]
        if last is None and time.monotonic() - start > args.timeout:
            print("graph_latency: no image on %s within %.0f s" % (args.image, args.timeout), file=sys.stderr)
            return 1
        if last is not None and time.monotonic() - last > args.idle:
            break
    rss = manager_peak_rss_mib(args.manager)
    with lock:
        n_images = len(image_wall) + len(latencies)
        if not latencies:
            print("graph_latency: no odometry matched an image (%d images, %d odometry)" % (n_images, state["odometry"]),
                  file=sys.stderr)
            return 1
        print("graph_latency: %d images, %d odometry messages, %d matched" % (n_images, state["odometry"], len(latencies)))
        print("graph_latency: image -> odometry [ms] median %.1f, 95 %% %.1f, max %.1f (one frame at 20 Hz = 50 ms)" %
              (percentile(latencies, 0.5), percentile(latencies, 0.95), max(latencies)))
    print("graph_latency: peak RSS of the nodelet manager '%s': %s" %
          (args.manager, "%.1f MiB" % rss if rss is not None else "not found"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
