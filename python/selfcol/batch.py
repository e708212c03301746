# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Batch checks of many frames on dask.distributed (or one Slurm array task).

usage::

    python -m selfcol.batch FRAMES... --out results.jsonl [--summary summary.json]
        [--workers N | --scheduler ADDRESS | --no-dask] [--shard I/N]
        [--distance D | --distance-rel K] [--method exact] [--worst K]
    python -m selfcol.batch --merge part-*.jsonl --out all.jsonl --summary summary.json

FRAMES are files, directories (their .obj and .ply files) or glob patterns.
Each frame is independent: the frames are mapped over a dask.distributed
cluster (a LocalCluster of ``--workers`` processes, or the scheduler at
``--scheduler``), each result is written as one JSON line as it completes,
and a summary follows. ``--no-dask`` checks in this process (a Slurm array
task with ``--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT``; then
``--merge`` the parts). Exit status: 0 nothing intersects, 1 some frame
intersects, 2 an error (some frame unreadable or invalid, or a usage error).

Per frame: file, index, vertices, triangles, distance, counts (vf, ee, ef,
intersecting_triangles), regions (contact regions: connected groups of
contacts), crossed_regions, the worst regions (most interferences, then
most contacts: their counts, the smallest distance and a vertex of the
region with its position), seconds (load, check), status ("clean",
"intersects" or "error" with "error": message).
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import json
import math
import os
import sys
import time
from typing import Any, Dict, Iterable, Iterator, List, Optional, TextIO, Tuple

import numpy as np

__all__ = ["check_frame", "check_options", "check_outputs", "expand_frames", "summarize",
           "run", "merge", "main"]


_METHODS = ("exact", "bvh", "exhaustive", "seed", "cone")


def expand_frames(patterns: Iterable[str]) -> List[str]:
    """Files, directories (their .obj/.ply files) and glob patterns, sorted
    within each argument, in argument order, without repeats. An argument
    that names no frame (a missing file, a glob that matches nothing, a
    directory without .obj or .ply files) raises ValueError naming it, so a
    typo fails a pipeline instead of checking nothing."""
    out: List[str] = []
    seen = set()
    for p in patterns:
        if os.path.isdir(p):
            found = sorted(os.path.join(p, f) for f in os.listdir(p)
                           if f.lower().endswith((".obj", ".ply")))
            if not found:
                raise ValueError("%s: a directory with no .obj or .ply file" % p)
        elif any(c in p for c in "*?["):
            found = sorted(glob.glob(p))
            if not found:
                raise ValueError("%s: no file matches this pattern" % p)
        elif not os.path.exists(p):
            raise ValueError("%s: no such file or directory" % p)
        else:
            found = [p]
        for f in found:
            if f not in seen:
                seen.add(f)
                out.append(f)
    return out


def _same_file(a: str, b: str) -> bool:
    """Whether paths a and b name one file: through symbolic and hard links
    (os.path.samefile when both exist), or by their resolved names when one
    does not exist yet (a link that dangles towards the other)."""
    try:
        if os.path.exists(a) and os.path.exists(b):
            return os.path.samefile(a, b)
    except OSError:
        pass
    return os.path.realpath(a) == os.path.realpath(b)


def check_outputs(outputs: Dict[str, Optional[str]], inputs: List[str]) -> None:
    """Refuses (ValueError, before anything is created or truncated) an
    output that is one of the inputs, or two outputs that are one file.
    ``outputs``: option name -> path (None when not given)."""
    given = [(name, path) for name, path in outputs.items() if path and path != "-"]
    for name, path in given:
        for inp in inputs:
            if _same_file(path, inp):
                raise ValueError("%s %s is the input %s: refusing to overwrite an input"
                                 % (name, path, inp))
    for i, (name, path) in enumerate(given):
        for other, opath in given[i + 1:]:
            if _same_file(path, opath):
                raise ValueError("%s and %s name the same file %s" % (name, other, path))


def check_options(distance: Optional[float] = None, distance_rel: float = 0.1,
                  method: str = "exact", worst: int = 3, threads: int = 1) -> None:
    """Refuses (ValueError naming the option) what every frame would refuse,
    before any frame is read."""
    if distance is not None and not (math.isfinite(distance) and distance >= 0):
        raise ValueError("--distance must be a finite number >= 0, got %r" % distance)
    if distance is None and not (math.isfinite(distance_rel) and distance_rel >= 0):
        raise ValueError("--distance-rel must be a finite number >= 0, got %r" % distance_rel)
    if str(method).lower() not in _METHODS:
        raise ValueError("--method %r is not one of %s" % (method, ", ".join(_METHODS)))
    from selfcol._selfcol_cffi import lib
    most = int(lib.SELFCOL_MAX_THREADS)
    if not 1 <= threads <= most:
        raise ValueError("--threads must be 1 to %d, got %d" % (most, threads))
    if worst < 0:
        raise ValueError("--worst must be >= 0, got %d" % worst)


def check_frame(path: str, index: int = 0, distance: Optional[float] = None,
                distance_rel: float = 0.1, method: str = "exact", worst: int = 3,
                threads: int = 1) -> Dict[str, Any]:
    """Checks one frame; never raises (errors are reported in the record)."""
    import selfcol
    from selfcol.io import read_mesh

    rec: Dict[str, Any] = {"file": path, "index": index}
    t0 = time.perf_counter()
    try:
        V, F = read_mesh(path)
        t1 = time.perf_counter()
        mesh = selfcol.Mesh(V, F)
        h = selfcol.Hierarchy(mesh)
        c = h.self_collide(distance, distance_rel, method=method, threads=threads)
        store = selfcol.Store()
        store.update(c)
        sc = store.contacts()
        counts = dict(c.counts)
        counts["intersecting_triangles"] = int(c.intersecting_triangles().shape[0])
        rec.update(vertices=int(V.shape[0]), triangles=int(F.shape[0]),
                   distance=c.distance_used, counts=counts)
        regions = sc.regions
        rec["regions"] = int(regions.shape[0])
        rec["crossed_regions"] = int(np.count_nonzero(regions["flags"] & 1))
        rec["worst_regions"] = _worst_regions(sc, mesh, worst)
        rec["seconds"] = {"load": t1 - t0, "check": time.perf_counter() - t1}
        rec["status"] = "intersects" if counts["ef"] else "clean"
    except Exception as exc:  # a frame's failure is data, not a crash of the batch
        rec["status"] = "error"
        rec["error"] = _frame_error(path, exc)
    return rec


def _frame_error(path: str, exc: BaseException) -> str:
    """The message of a frame's error, naming the file: the readers' own
    messages start with it; selfcol's errors name the array and the element."""
    text = str(exc) or type(exc).__name__
    if isinstance(exc, OSError) and exc.strerror:
        text = exc.strerror
    if text.startswith(path):
        return text
    return "%s: %s" % (path, text)


def _worst_regions(sc: Any, mesh: Any, k: int) -> List[Dict[str, Any]]:
    regions = sc.regions
    if regions.shape[0] == 0 or k <= 0:
        return []
    order = np.lexsort((-regions["contacts"].astype(np.int64),
                        -regions["interferences"].astype(np.int64)))[:k]
    region_of = sc.records["region"]
    dist = sc.records["distance"]
    first_vertex = sc.records["a"][:, 0]
    P = mesh.positions
    out = []
    for r in order:
        mine = np.nonzero(region_of == r)[0]
        v = int(first_vertex[mine[0]]) if mine.size else -1
        prox = mine[sc.records["kind"][mine] != 2] if mine.size else mine
        out.append({
            "region": int(r),
            "contacts": int(regions["contacts"][r]),
            "interferences": int(regions["interferences"][r]),
            "crossed": bool(regions["flags"][r] & 1),
            "min_distance": float(dist[prox].min()) if prox.size else None,
            "vertex": v,
            "position": P[v].tolist() if v >= 0 else None,
        })
    return out


def summarize(records: List[Dict[str, Any]], seconds: float, workers: int,
              startup: float = 0.0) -> Dict[str, Any]:
    """Totals over the frames, the worst frame, and the throughput (frames per
    second of the checks, after the cluster's start-up)."""
    ok = [r for r in records if r.get("status") != "error"]
    totals = {k: sum(r["counts"][k] for r in ok)
              for k in ("vf", "ee", "ef", "intersecting_triangles")}
    worst = max(ok, key=lambda r: (r["counts"]["ef"], r["counts"]["vf"] + r["counts"]["ee"]),
                default=None)
    return {
        "summary": True,
        "frames": len(records),
        "clean": sum(r.get("status") == "clean" for r in records),
        "intersecting": sum(r.get("status") == "intersects" for r in records),
        "errors": sum(r.get("status") == "error" for r in records),
        "totals": totals,
        "worst_frame": None if worst is None else {
            "file": worst["file"], "index": worst["index"], "counts": worst["counts"]},
        "workers": workers,
        "seconds": seconds,
        "startup_seconds": startup,
        "frames_per_second": (len(records) / (seconds - startup)) if seconds > startup else None,
    }


def _local_results(paths: List[str], indices: List[int], kw: Dict[str, Any]
                   ) -> Iterator[Dict[str, Any]]:
    for i, p in zip(indices, paths):
        yield check_frame(p, i, **kw)


def _dask_results(paths: List[str], indices: List[int], kw: Dict[str, Any], workers: int,
                  scheduler: Optional[str], timing: Dict[str, float]) -> Iterator[Dict[str, Any]]:
    from dask.distributed import Client, LocalCluster, as_completed

    from selfcol.batch import check_frame as task  # by reference, also under python -m

    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    client.wait_for_workers(1 if scheduler else workers)
    timing["ready"] = time.perf_counter()
    try:
        futures = client.map(task, paths, indices, pure=False, **kw)
        for fut in as_completed(futures):
            yield fut.result()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


@contextlib.contextmanager
def _output(path: str) -> Iterator[TextIO]:
    """The JSON Lines output: a file, or standard output for "-"."""
    if path == "-":
        yield sys.stdout
        sys.stdout.flush()
    else:
        with open(path, "w") as fh:
            yield fh


class _Progress:
    """Frames done, throughput and time left, on one line of standard error
    rewritten in place; only on a terminal (never into a log or a pipe), and
    not with --quiet."""

    def __init__(self, total: int, show: Optional[bool] = None) -> None:
        self.total, self.done, self.start = total, 0, time.perf_counter()
        self.show = sys.stderr.isatty() if show is None else show
        self.last = 0.0

    def step(self) -> None:
        self.done += 1
        now = time.perf_counter()
        if not self.show or (now - self.last < 0.2 and self.done < self.total):
            return
        self.last = now
        rate = self.done / max(now - self.start, 1e-9)
        left = (self.total - self.done) / rate if rate > 0 else 0.0
        sys.stderr.write("\rselfcol.batch: %d/%d frames, %.2f frames/s, %s left   "
                         % (self.done, self.total, rate, _duration(left)))
        if self.done == self.total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def _duration(seconds: float) -> str:
    s = int(round(seconds))
    return "%dh%02dm" % (s // 3600, s % 3600 // 60) if s >= 3600 else (
        "%dm%02ds" % (s // 60, s % 60) if s >= 60 else "%ds" % s)


def run(frames: List[str], out: str, summary: Optional[str] = None, workers: int = 1,
        scheduler: Optional[str] = None, use_dask: bool = True, shard: Optional[str] = None,
        progress: Optional[bool] = None, **kw: Any) -> Dict[str, Any]:
    """Checks the frames and writes JSON Lines to ``out`` ("-": standard
    output; one record per frame, then the summary line); returns the summary
    (also written to ``summary`` when given). ``progress``: a progress line
    on standard error (None: when it is a terminal)."""
    check_options(**{k: v for k, v in kw.items()
                     if k in ("distance", "distance_rel", "method", "worst", "threads")})
    shard_i, shard_n = _parse_shard(shard) if shard else (0, 1)
    all_paths = expand_frames(frames)
    check_outputs({"--out": out, "--summary": summary}, all_paths)
    indices = list(range(len(all_paths)))[shard_i::shard_n]
    paths = all_paths[shard_i::shard_n]
    start = time.perf_counter()
    timing = {"ready": start}
    records: List[Dict[str, Any]] = []
    results = (_dask_results(paths, indices, kw, workers, scheduler, timing)
               if use_dask and paths
               else _local_results(paths, indices, kw))
    bar = _Progress(len(paths), progress)
    with _output(out) as fh:
        for rec in results:
            records.append(rec)
            fh.write(json.dumps(rec, sort_keys=True) + "\n")
            fh.flush()
            bar.step()
        summ = summarize(sorted(records, key=lambda r: r["index"]),
                         time.perf_counter() - start, workers if use_dask else 1,
                         timing["ready"] - start)
        fh.write(json.dumps(summ, sort_keys=True) + "\n")
    write_summary(summ, summary)
    return summ


def _parse_shard(shard: str) -> Tuple[int, int]:
    try:
        i, n = (int(x) for x in shard.split("/"))
    except ValueError:
        raise ValueError("--shard must be I/N (two integers), got %r" % shard) from None
    if n < 1 or not 0 <= i < n:
        raise ValueError("--shard I/N needs 0 <= I < N, got %r" % shard)
    return i, n


def write_summary(summ: Dict[str, Any], summary: Optional[str]) -> None:
    """Writes the run's summary as indented JSON to `summary`, when given."""
    if summary:
        with open(summary, "w") as fh:
            json.dump(summ, fh, indent=1, sort_keys=True)
            fh.write("\n")


def merge(parts: List[str], out: str, summary: Optional[str] = None) -> Dict[str, Any]:
    """Joins the JSON Lines of several runs (e.g. Slurm array tasks)."""
    files = expand_frames_files(parts)
    check_outputs({"--out": out, "--summary": summary}, files)
    records: List[Dict[str, Any]] = []
    seconds = 0.0
    for p in files:
        with open(p) as fh:
            for line in fh:
                if not line.strip():
                    continue
                obj = json.loads(line)
                if obj.get("summary"):
                    seconds = max(seconds, float(obj.get("seconds") or 0.0))
                else:
                    records.append(obj)
    records.sort(key=lambda r: r["index"])
    with _output(out) as fh:
        for rec in records:
            fh.write(json.dumps(rec, sort_keys=True) + "\n")
        summ = summarize(records, seconds, len(parts))
        fh.write(json.dumps(summ, sort_keys=True) + "\n")
    write_summary(summ, summary)
    return summ


def expand_frames_files(patterns: Iterable[str]) -> List[str]:
    """The JSON Lines files of --merge: files and glob patterns; one that
    names no file raises ValueError naming it."""
    out: List[str] = []
    for p in patterns:
        found = sorted(glob.glob(p)) if any(c in p for c in "*?[") else [p]
        if not found:
            raise ValueError("%s: no file matches this pattern" % p)
        for f in found:
            if not os.path.isfile(f):
                raise ValueError("%s: no such file" % f)
        out.extend(found)
    return out


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m selfcol.batch",
                                 description="Check many frames for self-contacts, on "
                                 "dask.distributed or as one Slurm array task.")
    ap.add_argument("frames", nargs="*", help="files, directories or glob patterns")
    ap.add_argument("--out", required=True,
                    help="JSON Lines output (one line per frame); - for standard output")
    ap.add_argument("--quiet", action="store_true",
                    help="no progress line (shown on a terminal only) and no final line")
    ap.add_argument("--summary", help="also write the summary to this JSON file")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                    help="LocalCluster worker processes (default: the CPUs)")
    ap.add_argument("--scheduler", help="address of a running dask scheduler (tcp://host:8786)")
    ap.add_argument("--no-dask", action="store_true", help="check in this process")
    ap.add_argument("--shard", help="I/N: only every N-th frame from the I-th (Slurm arrays)")
    ap.add_argument("--merge", action="store_true", help="join the JSON Lines given as frames")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--distance", type=float, help="detection distance in mesh units")
    g.add_argument("--distance-rel", type=float, default=0.1,
                   help="d = K x mean edge length (default 0.1)")
    ap.add_argument("--method", default="exact", help="exact, bvh, exhaustive, seed, cone")
    ap.add_argument("--threads", type=int, default=1, help="threads per query (default 1)")
    ap.add_argument("--worst", type=int, default=3, help="worst regions kept per frame")
    args = ap.parse_args(argv)
    if not args.frames:
        ap.error("no %s given" % ("JSON Lines files" if args.merge else "frames"))
    if args.workers < 1:
        ap.error("--workers must be >= 1, got %d" % args.workers)
    try:
        check_options(args.distance, args.distance_rel, args.method, args.worst, args.threads)
    except ValueError as exc:
        ap.error(str(exc))
    try:
        if args.merge:
            summ = merge(args.frames, args.out, args.summary)
        else:
            summ = run(args.frames, args.out, args.summary, workers=max(1, args.workers),
                       scheduler=args.scheduler, use_dask=not args.no_dask, shard=args.shard,
                       progress=False if args.quiet else None, distance=args.distance, distance_rel=args.distance_rel,
                       method=args.method, worst=args.worst, threads=args.threads)
    except (OSError, ValueError) as exc:
        print("selfcol.batch: %s" % exc, file=sys.stderr)
        return 2
    if not args.quiet:
        # On standard error when the records go to standard output.
        print("selfcol.batch: %d frames, %d clean, %d intersecting, %d errors, %.2f frames/s "
              "(%.1f s, of which %.1f s start-up) -> %s"
              % (summ["frames"], summ["clean"], summ["intersecting"], summ["errors"],
                 summ["frames_per_second"] or 0.0, summ["seconds"],
                 summ.get("startup_seconds", 0.0),
                 "standard output" if args.out == "-" else args.out),
              file=sys.stderr if args.out == "-" else sys.stdout)
    if summ["errors"]:
        return 2
    return 1 if summ["intersecting"] else 0


if __name__ == "__main__":
    sys.exit(main())
