#!/usr/bin/env python3
"""tools/mpi/scaling_model.py — how pbrtrun-mpi would scale to many nodes: a model, not a run.

pbrtrun-mpi renders in passes (runtime/render/renderer.h); in each pass every tile's sums
travel to rank 0, which merges them in order before the next pass starts. So a pass costs

    compute = pixels * pass_spp * sample_seconds / (nodes * threads)      (all ranks)
    gather  = tiles * tile_bytes / bandwidth + tiles * merge_seconds       (rank 0, serial)
    tail    = one tile of one pass on one thread                           (the pass barrier)

and the frame is the sum over passes of max(compute, gather) + tail, since rank 0 takes
sums while the others render but cannot start the next pass before the last tile is in.
tile_bytes = 2 halves * (16 + 2 * filter radius)^2 pixels * 32 bytes (mpi_render.h).
Every input is a flag; the defaults are the assumptions printed with the table.
"""
import argparse
import math


def passes(spp):
    """The pass sizes of a render of spp samples (renderer.h): 1, 1, 2, 4, 8, then 8."""
    out, done = [], 0
    while done < spp:
        size = 1 if done == 0 else min(done, 8)
        size = min(size, spp - done)
        out.append(size)
        done += size
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--width", type=int, default=2048)
    p.add_argument("--height", type=int, default=858)
    p.add_argument("--spp", type=int, default=1024)
    # 20x killeroo-simple's 2.09 us measured here (pbrtrun, 1 thread, AMD EPYC): a guess at
    # Moana's heavier geometry and textures.
    p.add_argument("--sample-us", type=float, default=41.0,
                   help="seconds per sample per thread, in microseconds")
    p.add_argument("--threads", type=int, default=32, help="threads per node")
    p.add_argument("--filter-radius", type=float, default=2.0)
    p.add_argument("--gbps", type=float, default=10.0, help="rank 0's network, Gbit/s")
    p.add_argument("--merge-us", type=float, default=5.0, help="rank 0 per tile: receive+merge")
    p.add_argument("--nodes", default="1,8,64,512")
    a = p.parse_args()

    tiles = math.ceil(a.width / 16) * math.ceil(a.height / 16)
    side = 16 + 2 * math.ceil(a.filter_radius)
    tile_bytes = 2 * side * side * 32
    pixels = a.width * a.height
    sample_s = a.sample_us * 1e-6
    print(f"frame {a.width}x{a.height}, {a.spp} spp, {tiles} tiles of {tile_bytes / 1024:.1f} KiB, "
          f"{a.sample_us:g} us/sample/thread, {a.threads} threads/node, {a.gbps:g} Gbit/s "
          f"and {a.merge_us:g} us/tile at rank 0, {len(passes(a.spp))} passes")
    print("| nodes | frame time | speed-up | efficiency | rank 0 gather share |")
    print("|---:|---:|---:|---:|---:|")
    base = None
    for n in [int(x) for x in a.nodes.split(",")]:
        total = gather_total = 0.0
        gather = tiles * tile_bytes / (a.gbps * 1e9 / 8) + tiles * a.merge_us * 1e-6
        for size in passes(a.spp):
            compute = pixels * size * sample_s / (n * a.threads)
            tail = 256 * size * sample_s
            total += max(compute, gather if n > 1 else 0.0) + tail
            gather_total += gather if n > 1 else 0.0
        base = base or total * n
        print(f"| {n} | {total:,.1f} s | {base / total:.1f}x | {100 * base / total / n:.0f}% | "
              f"{100 * gather_total / total:.0f}% |")


if __name__ == "__main__":
    main()
