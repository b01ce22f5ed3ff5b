#!/usr/bin/env python3
"""A cluster model of sort-last rendering fitted to bench_mpi's lines.

Reads bench_mpi's output (scripts/bench_mpi.sh) on stdin and prints a Markdown
table of the modelled frame time for 10^9 particles at 1920x1080 on 32 to 256
ranks, and for the published anchor's case (Biedert et al. 2018: 2.1 M
particles at 4K in 2.4 s on 32 nodes).

The model, per frame:
  splat     = t_p * N / K / (c * e)    t_p: measured splat ms per particle, one thread (K = 1 line);
                                       c cores per rank at parallel efficiency e
  composite = sum over log2 K binary-swap steps s = 1.. of (alpha + B / 2^s / beta + P / 2^s * t_c)
              + gather of B (K - 1) / K to the root at beta
                                       B: partial bytes (8 per pixel: depth and chords), P pixels;
                                       t_c: measured combine ns per pixel (K = 2 line, loopback,
                                       an upper bound: it includes the shared-memory copies)
  finish    = t_f * P / P_measured / (c * e)   t_f: measured root finish (thickness, filters,
                                       normals, shading), one thread; runs once, on the root
Network: alpha = 2 us, beta = 12.5 GB/s (100 Gb/s InfiniBand EDR); c = 32, e = 0.8.
Reading the particles from disk is not modelled.
"""
import math
import re
import sys

ALPHA_S = 2e-6
BETA_BPS = 12.5e9
CORES = 32
EFFICIENCY = 0.8


def parse(lines):
    ranks, roots = {}, {}
    rank_re = re.compile(r"sort-last K=(\d+) rank (\d+)\s+(\d+)x(\d+)\s+(\d+) particles\s+splat\s+([\d.]+) ms\s+"
                         r"composite\s+([\d.]+) ms \(reduce-scatter\s+([\d.]+), gather\s+([\d.]+)\)\s+"
                         r"sent\s+([\d.]+) MB of\s+([\d.]+) MB")
    root_re = re.compile(r"sort-last K=(\d+) root\s+(\d+)x(\d+)\s+(\d+) particles\s+finish\s+([\d.]+) ms\s+frame\s+([\d.]+) ms")
    for line in lines:
        m = rank_re.search(line)
        if m:
            k, r = int(m[1]), int(m[2])
            ranks.setdefault(k, {})[r] = dict(w=int(m[3]), h=int(m[4]), n=int(m[5]), splat=float(m[6]),
                                              composite=float(m[7]), reduce=float(m[8]), gather=float(m[9]),
                                              sent=float(m[10]), image=float(m[11]))
        m = root_re.search(line)
        if m:
            roots[int(m[1])] = dict(w=int(m[2]), h=int(m[3]), n=int(m[4]), finish=float(m[5]), frame=float(m[6]))
    return ranks, roots


def model(n, w, h, k, t_p_ms, t_c_ns, t_f_ms, p_measured):
    pixels = w * h
    image_bytes = 8 * pixels
    speed = CORES * EFFICIENCY
    splat = t_p_ms * 1e-3 * n / k / speed
    steps = int(math.ceil(math.log2(k))) if k > 1 else 0
    swap = sum(ALPHA_S + image_bytes / 2 ** s / BETA_BPS + pixels / 2 ** s * t_c_ns * 1e-9 for s in range(1, steps + 1))
    gather = image_bytes * (k - 1) / k / BETA_BPS if k > 1 else 0.0
    finish = t_f_ms * 1e-3 * pixels / p_measured / speed
    return splat, swap + gather, finish


def main():
    ranks, roots = parse(sys.stdin.readlines())
    if 1 not in ranks or 1 not in roots:
        sys.exit("mpi_model: no K=1 lines on stdin (run scripts/bench_mpi.sh)")
    one = ranks[1][0]
    t_p = one["splat"] / one["n"]
    p_measured = one["w"] * one["h"]
    t_f = roots[1]["finish"]
    t_c = 0.0
    if 2 in ranks:  # combine cost per pixel: the reduce-scatter of K = 2 over the pixels it combined (half the image)
        t_c = min(r["reduce"] for r in ranks[2].values()) * 1e6 / (p_measured / 2)
    print("Measured, this machine (loopback, one thread per process):")
    print()
    # A process waits in the composite for the last to finish its splat: the
    # smallest composite time (the last to arrive's) is the composite itself.
    print("| K | particles per rank | splat per rank (ms, min-max) | composite (ms, last to arrive) | "
          "composite incl. waiting (ms, max) | MB sent per rank (binary swap + gather) | root finish (ms) | frame (ms) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for k in sorted(ranks):
        rs = list(ranks[k].values())
        print(f"| {k} | {min(r['n'] for r in rs):.0f}-{max(r['n'] for r in rs):.0f} | "
              f"{min(r['splat'] for r in rs):.1f}-{max(r['splat'] for r in rs):.1f} | "
              f"{min(r['composite'] for r in rs):.1f} | {max(r['composite'] for r in rs):.1f} | "
              f"{max(r['sent'] for r in rs):.2f} of {rs[0]['image']:.2f} | "
              f"{roots[k]['finish']:.1f} | {roots[k]['frame']:.1f} |")
    print()
    print(f"Fitted: t_p = {t_p * 1e3:.3f} us per particle, t_c = {t_c:.2f} ns per pixel and step, "
          f"finish {t_f:.1f} ms at {one['w']}x{one['h']} (one thread).")
    print()
    print("Modelled: 10^9 particles at 1920x1080 (ranks of 32 cores, 100 Gb/s InfiniBand):")
    print()
    print("| ranks | splat (s) | composite (ms) | finish (ms) | frame (s) | particles per rank |")
    print("| --- | --- | --- | --- | --- | --- |")
    for k in (32, 64, 128, 256):
        s, c, f = model(1e9, 1920, 1080, k, t_p, t_c, t_f, p_measured)
        print(f"| {k} | {s:.2f} | {c * 1e3:.1f} | {f * 1e3:.1f} | {s + c + f:.2f} | {1e9 / k / 1e6:.1f} M |")
    s, c, f = model(2.1e6, 3840, 2160, 32, t_p, t_c, t_f, p_measured)
    print()
    print(f"Anchor: 2.1 M particles at 3840x2160 on 32 ranks: modelled {(s + c + f) * 1e3:.0f} ms "
          f"(splat {s * 1e3:.1f}, composite {c * 1e3:.1f}, finish {f * 1e3:.1f}); Biedert et al. 2018: 2.4 s on 32 nodes.")


if __name__ == "__main__":
    main()
