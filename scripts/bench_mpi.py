#!/usr/bin/env python3
"""vdb_render on several MPI ranks (docs/scaling.md): strong scaling of a heavy render, the 1280x720
twill reference, from 1 to 2 ranks with one thread each, and the scaling model of docs/scaling.md
fitted to what the runs measure.

Runs, each timed as a whole process by /usr/bin/time -v (wall time and peak memory):
  solo      vdb_render without mpirun, one thread
  1 rank    mpirun -n 1, one thread
  2 ranks   mpirun -n 2, one thread each
All three images must be identical to the byte. The 2-rank report gives each rank's seconds in tiles,
in claims of the shared counter and in the final sum of the films; from them: the communication
share (claims and sum over the render's seconds, at the slowest rank) and the load imbalance (the
slowest rank's tile seconds over the mean). Two more renders, of an eighth of the samples with the
AOV "time", give the cost of every 8 x 8 tile (the lesser of the two), which the model replays for
larger jobs.

The model (predict()): ranks claim batches of 1 to 4 tiles per thread (fewer as the tiles run
out) first come, first served, as vdb_render does; replaying the measured tile costs, scaled to a job's total core-seconds, through
that list schedule gives the render's makespan at P ranks. Added to it: the setup every rank repeats
(reading the medium, building the majorant; measured here as process seconds minus render seconds,
scaled by the medium's size for another job), one claim's latency per batch, and a ring allreduce of
the film (2 (P - 1) / P x bytes / bandwidth + 2 (P - 1) x latency).
Results: bench-out/mpi_report.md and .json.
Usage: scripts/bench_mpi.py [--build build] [--out bench-out] [--spp 32] [--res 1280x720]
       [--twill-res 256] [--threads-per-rank 16] [--bandwidth-gbs 1.25] [--latency-us 50]
"""
import argparse
import heapq
import json
import os
import pathlib
import re
import subprocess
import sys

SCENE = ["--view", "+z", "--env", "0.3", "--sun", "1,0.6,-1.2,3"]
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
FILM_BYTES_PER_PIXEL = 56  # a pixel's sums in the film: 6 doubles and a 32-bit count, padded (render_image.cpp)
# The paper's velvet reference (downsampling paper, Table 2): 74 core-hours at 1280 x 720.
VELVET_CORE_SECONDS = 74 * 3600.0


def timed(command, env=None):
    """Runs command under /usr/bin/time -v: (wall seconds, peak resident MB)."""
    full_env = dict(os.environ, **(env or {}))
    result = subprocess.run(["/usr/bin/time", "-v"] + command, env=full_env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"bench_mpi: failed: {' '.join(command)}\n{result.stderr}")
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", result.stderr)
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", result.stderr)
    seconds = int(wall.group(1) or 0) * 3600 + int(wall.group(2)) * 60 + float(wall.group(3))
    return seconds, int(rss.group(1)) / 1024.0


def render(build, medium, out, args, name, ranks):
    image, report = out / f"{name}.exr", out / f"{name}.json"
    command = [str(build / "bin" / "vdb_render"), str(medium), "-o", str(image), "--report", str(report)] + args
    if ranks:
        command = ["mpirun", "-q", "-n", str(ranks)] + command
    wall, rss = timed(command, MPI_ENV if ranks else None)
    return {"wall_seconds": wall, "peak_mb": rss, "report": json.loads(report.read_text()), "image": image}


def batch_size(tiles, claimed, ranks, threads):
    """vdb_render's guided batches (render_image.cpp, batchSize): 4 tiles per thread while much is
    left, down to 1 as the tiles run out."""
    left = max(0, tiles - claimed)
    return threads * min(4, max(1, left // (2 * ranks * threads)))


def batch_count(tiles, ranks, threads):
    count, claimed = 0, 0
    while claimed < tiles:
        claimed += batch_size(tiles, claimed, ranks, threads)
        count += 1
    return count


def schedule(tile_costs, ranks, threads, claim_seconds):
    """Makespan of vdb_render's list schedule: each rank, when free, claims the next batch
    (batch_size) and renders it with its threads (the batch takes its cost / threads, or its
    largest tile if that is longer)."""
    free = [(0.0, r) for r in range(ranks)]
    heapq.heapify(free)
    end = 0.0
    first = 0
    while first < len(tile_costs):
        batch = batch_size(len(tile_costs), first, ranks, threads)
        costs = tile_costs[first:first + batch]
        first += batch
        start, rank = heapq.heappop(free)
        finish = start + claim_seconds + max(sum(costs) / threads, max(costs))
        end = max(end, finish)
        heapq.heappush(free, (finish, rank))
    return end


def tile_statistics(values):
    """vdb_render's "tile_seconds" of the report, for a list of tile costs."""
    ordered = sorted(values)
    total = sum(ordered)

    def quantile(q):
        return ordered[min(len(ordered) - 1, int(q * len(ordered)))]
    return {"tiles": len(values), "total": total, "mean": total / len(values), "median": quantile(0.5),
            "p90": quantile(0.9), "p99": quantile(0.99), "max": ordered[-1], "values": values}


def ring_allreduce_seconds(ranks, film_bytes, bandwidth, latency):
    return 0.0 if ranks == 1 else 2 * (ranks - 1) / ranks * film_bytes / bandwidth + 2 * (ranks - 1) * latency


def predict(tile_costs, core_seconds, ranks, threads, setup_seconds, claim_seconds, sum_seconds):
    scale = core_seconds / sum(tile_costs)
    scaled = [c * scale for c in tile_costs]
    render = schedule(scaled, ranks, threads, claim_seconds)
    reduce = sum_seconds
    return {"ranks": ranks, "threads": threads, "setup": setup_seconds, "render": render, "sum": reduce,
            "total": setup_seconds + render + reduce}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="bench-out")
    parser.add_argument("--spp", type=int, default=32)
    parser.add_argument("--res", default="1280x720")
    parser.add_argument("--twill-res", type=int, default=256)
    parser.add_argument("--threads-per-rank", type=int, default=16, help="the model's cluster nodes")
    parser.add_argument("--bandwidth-gbs", type=float, default=1.25, help="the model's network: GB/s (10 GbE)")
    parser.add_argument("--latency-us", type=float, default=50, help="the model's network: one message's latency")
    parser.add_argument("--medium-gb", type=float, default=4.0,
                        help="the model's medium: GB every rank reads (an assumption for the velvet, not the paper's figure)")
    parser.add_argument("--fs-gbs", type=float, default=10.0, help="the model's shared file system: GB/s for all readers")
    parser.add_argument("--node-read-gbs", type=float, default=1.0, help="the model's node: GB/s one rank reads and decodes")
    a = parser.parse_args()
    build, out = pathlib.Path(a.build).resolve(), pathlib.Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    medium = out / f"twill{a.twill_res}.vdb"
    if not medium.exists():
        subprocess.run([str(build / "bin" / "vdb_make_medium"), "twill", "--res", str(a.twill_res), "-o", str(medium)], check=True)
    width, height = (int(v) for v in a.res.split("x"))
    args = ["--res", a.res, "--spp", str(a.spp), "--seed", "1", "-j", "1"] + SCENE
    print(f"bench_mpi: twill {a.twill_res}^3 at {a.res}, {a.spp} spp, one thread per process", file=sys.stderr)
    solo = render(build, medium, out, args, "mpi_solo", 0)
    one = render(build, medium, out, args, "mpi_1rank", 1)
    two = render(build, medium, out, args, "mpi_2ranks", 2)
    identical = solo["image"].read_bytes() == one["image"].read_bytes() == two["image"].read_bytes()
    # The tiles' costs, from renders of an eighth of the samples with the AOV "time" (its costs scale
    # with spp): the least of two runs per tile, since a busy machine only ever adds time.
    tile_args = ["--res", a.res, "--spp", str(max(1, a.spp // 8)), "--seed", "1", "-j", "1", "--aov", "time"] + SCENE
    timed_tiles = render(build, medium, out, tile_args, "mpi_tile_costs", 0)
    again = render(build, medium, out, tile_args, "mpi_tile_costs_again", 0)
    least = [min(p, q) for p, q in zip(timed_tiles["report"]["tile_seconds"]["values"], again["report"]["tile_seconds"]["values"])]
    timed_tiles["report"]["tile_seconds"] = tile_statistics(least)

    ranks = two["report"]["ranks"]
    render_seconds = two["report"]["seconds"]
    tile_mean = sum(r["tile_seconds"] for r in ranks) / len(ranks)
    imbalance = max(r["tile_seconds"] for r in ranks) / tile_mean
    slowest = max(ranks, key=lambda r: r["tile_seconds"])
    communication = (slowest["claim_seconds"] + slowest["sum_seconds"]) / render_seconds
    tiles = timed_tiles["report"]["tile_seconds"]["tiles"]
    claims_per_rank = batch_count(tiles, 2, 1) / 2  # one thread per rank, 2 ranks
    claim_seconds = min(r["claim_seconds"] for r in ranks) / claims_per_rank
    film_bytes = width * height * FILM_BYTES_PER_PIXEL
    sum_seconds = min(r["sum_seconds"] for r in ranks)  # the last rank to arrive waits least: the transfer itself
    setup_seconds = one["wall_seconds"] - one["report"]["seconds"]

    # Per-tile costs of the 1-rank run, in the order the counter hands them out (row by row).
    time_image = dict(timed_tiles["report"]["tile_seconds"])
    tile_costs = time_image.pop("values")
    measured_two = solo["wall_seconds"] / two["wall_seconds"]
    # On this machine: the measured claim and sum; on the velvet's cluster: the network's.
    # (the tiles' costs scaled to the 1-rank render's seconds: they were timed at fewer samples)
    model_two = predict(tile_costs, one["report"]["seconds"], 2, 1, setup_seconds, claim_seconds, sum_seconds)
    model_one = predict(tile_costs, one["report"]["seconds"], 1, 1, setup_seconds, claim_seconds, 0.0)
    bandwidth, latency = a.bandwidth_gbs * 1e9, a.latency_us * 1e-6
    # Every rank reads the medium: one rank's read, or the file system shared by all, whichever is slower.
    def load(p):
        return max(a.medium_gb / a.node_read_gbs, p * a.medium_gb / a.fs_gbs)
    velvet = [predict(tile_costs, VELVET_CORE_SECONDS, p, a.threads_per_rank, load(p), 2 * latency,
                      ring_allreduce_seconds(p, film_bytes, bandwidth, latency))
              for p in (1, 16, 64, 256, 1024)]
    for v in velvet:
        v["speedup"] = velvet[0]["total"] / v["total"]

    results = {
        "medium": f"twill --res {a.twill_res}", "resolution": a.res, "spp": a.spp,
        "identical": identical, "tile_spp": max(1, a.spp // 8),
        "runs": {name: {"wall_seconds": r["wall_seconds"], "render_seconds": r["report"]["seconds"], "peak_mb": r["peak_mb"]}
                 for name, r in (("solo", solo), ("1 rank", one), ("2 ranks", two))},
        "speedup_1_to_2_ranks": one["wall_seconds"] / two["wall_seconds"],
        "speedup_solo_to_2_ranks": measured_two,
        "render_speedup_1_to_2_ranks": one["report"]["seconds"] / render_seconds,
        "ranks": ranks, "communication_share": communication, "imbalance": imbalance,
        "claim_seconds": claim_seconds, "film_bytes": film_bytes, "sum_seconds": sum_seconds, "setup_seconds": setup_seconds,
        "tile_seconds": time_image,
        "model": {"two_ranks": model_two, "one_rank": model_one,
                  "predicted_speedup_1_to_2": model_one["total"] / model_two["total"],
                  "velvet": velvet, "threads_per_rank": a.threads_per_rank,
                  "bandwidth_gbs": a.bandwidth_gbs, "latency_us": a.latency_us, "medium_gb": a.medium_gb,
                  "fs_gbs": a.fs_gbs, "node_read_gbs": a.node_read_gbs}}
    (out / "mpi_report.json").write_text(json.dumps(results, indent=1) + "\n")
    (out / "mpi_report.md").write_text(markdown(results))
    print((out / "mpi_report.md").read_text())
    if not identical:
        sys.exit("bench_mpi: the images of the three runs differ")


def markdown(r):
    runs = r["runs"]
    lines = [f"# vdb_render on MPI ranks: {r['medium']} at {r['resolution']}, {r['spp']} spp, one thread per process", "",
             "| run | process seconds | render seconds | peak memory (MB) |", "|---|---|---|---|"]
    for name, v in runs.items():
        lines.append(f"| {name} | {v['wall_seconds']:.1f} | {v['render_seconds']:.1f} | {v['peak_mb']:.0f} |")
    lines += ["",
              f"- images of the three runs identical to the byte: {'yes' if r['identical'] else 'NO'}",
              f"- strong scaling, 1 to 2 ranks (process seconds): {r['speedup_1_to_2_ranks']:.2f}x "
              f"(solo to 2 ranks {r['speedup_solo_to_2_ranks']:.2f}x; render seconds alone {r['render_speedup_1_to_2_ranks']:.2f}x)",
              f"- communication share at 2 ranks (claims and the final sum, slowest rank, over the render): "
              f"{100 * r['communication_share']:.2f}%",
              f"- load imbalance at 2 ranks (slowest rank's tile seconds over the mean): {r['imbalance']:.4f}",
              f"- one claim: {1e6 * r['claim_seconds']:.1f} us; the film's sum ({r['film_bytes'] / 1e6:.1f} MB): "
              f"{r['sum_seconds']:.3f} s; setup every rank repeats: {r['setup_seconds']:.2f} s",
              f"- tiles: {r['tile_seconds']['tiles']}, mean {1e3 * r['tile_seconds']['mean']:.3f} ms, median "
              f"{1e3 * r['tile_seconds']['median']:.3f} ms, p99 {1e3 * r['tile_seconds']['p99']:.3f} ms, max "
              f"{1e3 * r['tile_seconds']['max']:.3f} ms (one process, {r['tile_spp']} spp)",
              "", "## Model", "",
              f"Predicted speed-up 1 to 2 ranks on this machine: {r['model']['predicted_speedup_1_to_2']:.2f}x "
              f"(measured {r['speedup_1_to_2_ranks']:.2f}x).", "",
              f"The paper's velvet reference (74 core-hours at 1280x720), ranks of {r['model']['threads_per_rank']} threads, "
              f"a network of {r['model']['bandwidth_gbs']} GB/s and {r['model']['latency_us']} us per message, "
              f"this twill's tile costs scaled to it, and a medium of {r['model']['medium_gb']} GB that every rank reads "
              f"(at most {r['model']['node_read_gbs']} GB/s each, {r['model']['fs_gbs']} GB/s for all from the shared "
              f"file system): the medium's size and the file system are assumptions, not measurements.", "",
              "| ranks | reading the medium (s) | render (s) | film sum (s) | total (s) | speed-up over 1 rank |",
              "|---|---|---|---|---|---|"]
    for v in r["model"]["velvet"]:
        lines.append(f"| {v['ranks']} | {v['setup']:.1f} | {v['render']:.0f} | {v['sum']:.3f} | {v['total']:.0f} | {v['speedup']:.1f}x |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
