# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Charts and tables of the selfcol benchmarks (issue 5).

Reads tools/bench/results/SUBSET.csv and .meta (written by tools/bench/run.sh)
and writes, for each detection distance (d = 0.1 and 0.5 x mean edge):
  docs/bench-speed-accuracy-d*.png  time per frame against missed contacts
  docs/bench-scaling-d*.png         time against triangles (refit, query, build)
  docs/bench-culling-d*.png         share of node pairs culled per criterion
and rewrites the generated parts of docs/benchmarks.md (between the
'<!-- generated:NAME -->' and '<!-- /generated:NAME -->' markers), so that
`make bench && make plot` reproduces the page from the run.
Run it through tools/plot/plot.sh, which finds a Python with matplotlib.
"""
import argparse
import csv
import math
import os
import re
import sys

try:
    import matplotlib

    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt  # noqa: E402
    import matplotlib.ticker  # noqa: E402
except ImportError:  # --check compares the tables and draws nothing
    matplotlib = plt = None

# EXACT-VF (vertex-triangle proximities only) is the like-for-like partner
# of BULLET, which has no edge-edge test and reports no crossing; its misses
# count against the VF set only, Bullet's against the whole exact set.
# A method on more than one thread (column `threads`) is a series of its own,
# "EXACT x2" for two (bench rows of the larger cases, ipc-toolkit in bench-full).
METHODS = ["EXHAUSTIVE", "BVH", "EXACT", "EXACT x2", "SEED", "CONE", "BVH+libccd", "EXACT-VF",
           "BULLET", "IPCTK", "IPCTK x2"]
STYLE = {
    "EXHAUSTIVE": ("tab:gray", "s"),
    "BVH": ("tab:blue", "o"),
    "EXACT": ("tab:green", "D"),
    "EXACT x2": ("darkgreen", "d"),
    "SEED": ("tab:orange", "^"),
    "CONE": ("tab:red", "v"),
    "BVH+libccd": ("tab:purple", "P"),
    "EXACT-VF": ("tab:olive", "d"),
    "BULLET": ("black", "X"),
    "IPCTK": ("tab:cyan", "*"),  # ipc-toolkit, bench-full only
    "IPCTK x2": ("darkcyan", "*"),
}
FACTORS = ["0.1", "0.5"]


def method_of(r):
    threads = int(float(r.get("threads") or 1))
    return (r["method"] + ("+libccd" if r["narrow"] == "libccd" else "")
            + (" x%d" % threads if threads > 1 else ""))


def load(results, subset):
    """The rows of SUBSET.csv, the contact-store rows (method STORE,
    STORE-FIRST: tools/bench/selfcol_bench.c) apart, and the .meta."""
    path = os.path.join(results, subset + ".csv")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["m"] = method_of(r)
        r["df"] = "%g" % float(r["d_factor"])
        for k in list(r):
            if k not in ("subset", "case", "scene", "method", "narrow", "reference", "note", "m", "df"):
                # A column missing from a row (an older writer) reads as 0.
                r[k] = float(r[k]) if r[k] not in (None, "") else 0.0
    # The store rows time selfcol_store_update, not a query: they have a
    # table of their own and stay out of the charts and the other tables.
    store = [r for r in rows if r["method"].startswith("STORE")]
    rows = [r for r in rows if not r["method"].startswith("STORE")]
    meta = {}
    mpath = os.path.join(results, subset + ".meta")
    if os.path.exists(mpath):
        with open(mpath) as f:
            for line in f:
                if "=" in line:
                    k, v = line.rstrip("\n").split("=", 1)
                    meta[k] = v
    return rows, meta, store


def cases_in_order(rows):
    seen = []
    for r in rows:
        if r["case"] not in seen:
            seen.append(r["case"])
    return seen


def pick(rows, case, df, m):
    for r in rows:
        if r["case"] == case and r["df"] == df and r["m"] == m:
            return r
    return None


def representative_cases(rows):
    """Per scene: the largest case that has a Bullet row, else the largest."""
    by_scene = {}
    for r in rows:
        by_scene.setdefault(r["scene"], {})[r["case"]] = r["triangles"]
    out = []
    for scene, cases in by_scene.items():
        with_bullet = [c for c in cases if any(r["case"] == c and r["m"] == "BULLET" for r in rows)]
        pool = with_bullet or list(cases)
        out.append(max(pool, key=lambda c: cases[c]))
    return out


def fmt_ms(x):
    if x is None:
        return "-"
    if x >= 100:
        return "%.0f" % x
    if x >= 10:
        return "%.1f" % x
    if x >= 0.1:
        return "%.2f" % x
    return "%.3f" % x


def fmt_int(x):
    return "%d" % int(x)


def kilo(n):
    n = int(n)
    if n >= 1000000:
        return "%.2fM" % (n / 1e6)
    if n >= 1000:
        return "%.0fk" % (n / 1e3) if n >= 10000 else "%.1fk" % (n / 1e3)
    return str(n)


# ---------------------------------------------------------------------------
# Charts

def chart_speed_accuracy(rows, df, path, note):
    cases = representative_cases(rows)
    n = len(cases)
    cols = 4 if n > 6 else 3
    nrows = max(1, math.ceil(n / cols))
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.4 * nrows), squeeze=False)
    for i, case in enumerate(cases):
        ax = axes[i // cols][i % cols]
        ref_total = None
        top = 1.0
        for m in METHODS:
            r = pick(rows, case, df, m)
            if r is None:
                continue
            color, marker = STYLE[m]
            x = max(r["frame_ms"], 1e-4)
            ax.scatter([x], [r["misses"]], color=color, marker=marker, s=55, label=m, zorder=3)
            if r["extras"] > 0:  # reported pairs outside the exact sets
                ax.annotate("+%d extra" % r["extras"], (x, r["misses"]), fontsize=6,
                            xytext=(4, 4), textcoords="offset points", color=color)
            # EXACT-VF's reference is the VF set alone: label with the whole set.
            ref_total = max(ref_total or 0, r["ref_vf"] + r["ref_ee"] + r["ref_ef"])
            top = max(top, r["misses"], ref_total)
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # labels collide on narrow ranges
        ax.set_yscale("symlog", linthresh=1)
        ax.set_ylim(-0.5, top * 3)
        tri = next(r["triangles"] for r in rows if r["case"] == case)
        scale = next(r["scale"] for r in rows if r["case"] == case)
        title = "%s (%s tri%s)" % (case, kilo(tri), ", x%g" % scale if scale != 1 else "")
        if case.endswith("-raw"):  # left unscaled on purpose: inside Bullet's dead zone
            title = "%s (%s tri, 1 cm edges, unscaled)" % (case, kilo(tri))
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("frame time, ms (refit + query; log)", fontsize=8)
        ax.set_ylabel("missed contacts (of %s)" % fmt_int(ref_total or 0), fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        ax.tick_params(labelsize=7)
    for j in range(n, nrows * cols):
        axes[j // cols][j % cols].axis("off")
    handles = [plt.Line2D([], [], color=STYLE[m][0], marker=STYLE[m][1], linestyle="", label=m)
               for m in METHODS]
    fig.legend(handles=handles, loc="lower center", ncol=len(METHODS), fontsize=8, frameon=False,
               title="EXACT-VF: VF only, misses against the VF set; BULLET (VF only): misses "
               "against all VF/EE/EF contacts", title_fontsize=7)
    fig.suptitle("Speed against accuracy, d = %s x mean edge. %s" % (df, note), fontsize=10)
    fig.tight_layout(rect=(0, 0.06, 1, 0.95))
    fig.savefig(path, dpi=90)
    plt.close(fig)


def chart_scaling(rows, df, path):
    scenes = [s for s in ("flat", "sphere", "crumpled") if any(r["scene"] == s for r in rows)]
    fig, axes = plt.subplots(1, max(1, len(scenes)), figsize=(5.2 * max(1, len(scenes)), 4.3),
                             squeeze=False)
    for i, scene in enumerate(scenes):
        ax = axes[0][i]
        # One case per size: the crumpled scene has several seeds at 20k; take seed 1.
        cases = {}
        for r in rows:
            if r["scene"] == scene and r["df"] == df:
                cases.setdefault(r["triangles"], r["case"])
        sizes = sorted(cases)

        def series(m, key):
            xs, ys = [], []
            for t in sizes:
                r = pick(rows, cases[t], df, m)
                if r is not None and r[key] > 0:
                    xs.append(t)
                    ys.append(r[key])
            return xs, ys

        x, y = series("BVH", "build_ms")
        ax.plot(x, y, color="tab:brown", linestyle=":", marker=".", label="selfcol build")
        x, y = series("BVH", "refit_ms")
        ax.plot(x, y, color="black", linestyle="--", marker=".", label="selfcol refit")
        for m in ("BVH", "EXACT", "SEED", "CONE"):
            x, y = series(m, "query_ms")
            if x:
                ax.plot(x, y, color=STYLE[m][0], marker=STYLE[m][1], markersize=4,
                        label="%s query" % m)
        x, y = series("BULLET", "refit_ms")
        if x:
            ax.plot(x, y, color="gray", linestyle="--", marker="x", label="Bullet refit")
        x, y = series("BULLET", "query_ms")
        if x:
            ax.plot(x, y, color="black", marker="X", label="Bullet self-collision")
        x, y = series("BULLET", "build_ms")
        if x:
            ax.plot(x, y, color="gray", linestyle=":", marker="x", label="Bullet build")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title("%s" % scene, fontsize=10)
        ax.set_xlabel("triangles", fontsize=9)
        ax.set_ylabel("time, ms (median)", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Scaling, d = %s x mean edge: refit and query separated" % df, fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    fig.savefig(path, dpi=90)
    plt.close(fig)


def chart_culling(rows, df, path):
    cases = representative_cases(rows)
    methods = ["BVH", "SEED", "CONE", "EXACT"]
    labels, box, curv, adj, refused = [], [], [], [], []
    for case in cases:
        for m in methods:
            r = pick(rows, case, df, m)
            if r is None or r["nodes_visited"] <= 0:
                continue
            v = r["nodes_visited"]
            labels.append("%s %s" % (case, m))
            box.append(r["culled_box"] / v)
            curv.append(r["culled_curvature"] / v)
            adj.append(r["culled_adjacency"] / v)
            # Older CSVs (before stats version 3) have no contour columns.
            refused.append(r.get("contour_refused", 0.0) / v)
    fig, ax = plt.subplots(figsize=(8.5, max(3.0, 0.19 * len(labels) + 1.2)))
    y = list(range(len(labels)))
    ax.barh(y, box, color="tab:blue", label="box (pairs apart)")
    ax.barh(y, curv, left=box, color="tab:green", label="curvature (+ contour for EXACT)")
    ax.barh(y, adj, left=[a + b for a, b in zip(box, curv)], color="tab:orange",
            label="adjacency (joint curvature; + joint contour for EXACT)")
    ax.barh(y, refused, left=[a + b + c for a, b, c in zip(box, curv, adj)], color="lightgray",
            hatch="//", edgecolor="gray",
            label="kept by the contour test (EXACT: curvature held, contour not proven)")
    ax.set_yticks(y)
    ax.set_yticklabels(labels, fontsize=6)
    ax.invert_yaxis()
    ax.set_xlim(0, 1)
    ax.set_xlabel("share of the nodes and node pairs examined that were culled", fontsize=8)
    ax.set_title("Culling by criterion, d = %s x mean edge" % df, fontsize=10)
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, axis="x", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# ---------------------------------------------------------------------------
# Tables

def table_machine(meta):
    keys = ["cpu", "cores", "memory_kb", "kernel", "compiler", "build_type", "bullet", "threads",
            "frames", "commit", "date", "runtime_s", "command"]
    out = ["| | |", "|---|---|"]
    for k in keys:
        if k in meta:
            out.append("| %s | %s |" % (k, meta[k].replace("|", "/")))
    return "\n".join(out)


def table_cases(rows, df):
    cols = METHODS
    out = ["| case | tri | contacts (VF/EE/EF) | ref | build ms | refit ms | "
           + " | ".join("%s frame ms (miss/extra)" % c for c in cols) + " |",
           "|---" * (6 + len(cols)) + "|"]
    for case in cases_in_order(rows):
        base = pick(rows, case, df, "BVH")
        if base is None:
            continue
        cells = []
        for m in cols:
            r = pick(rows, case, df, m)
            if r is None:
                cells.append("")
            else:
                cells.append("%s (%s/%s)" % (fmt_ms(r["frame_ms"]), fmt_int(r["misses"]),
                                             fmt_int(r["extras"])))
        out.append("| %s | %s | %s/%s/%s | %s | %s | %s | %s |" % (
            case, kilo(base["triangles"]), fmt_int(base["ref_vf"]), fmt_int(base["ref_ee"]),
            fmt_int(base["ref_ef"]), base["reference"], fmt_ms(base["build_ms"]),
            fmt_ms(base["refit_ms"]), " | ".join(cells)))
    return "\n".join(out)


def largest(rows, scene, df, m):
    best = None
    for r in rows:
        if r["scene"] == scene and r["df"] == df and r["m"] == m:
            if best is None or r["triangles"] > best["triangles"]:
                best = r
    return best


def table_headlines(rows):
    out = ["| measure | d = 0.1 x | d = 0.5 x | target |", "|---|---|---|---|"]

    def both(fn):
        return [fn(df) for df in FACTORS]

    def ratio_line(scene, m, target):
        def f(df):
            r = largest(rows, scene, df, m)
            if r is None or r["refit_ms"] <= 0:
                return "-"
            return "%.2f%% (%s query %s ms / refit %s ms, %s tri)" % (
                100 * r["query_ms"] / r["refit_ms"], m, fmt_ms(r["query_ms"]),
                fmt_ms(r["refit_ms"]), kilo(r["triangles"]))
        a, b = both(f)
        out.append("| %s, largest size: query / refit (%s) | %s | %s | %s |" % (scene, m, a, b, target))

    for m in ("EXACT", "BVH", "SEED"):
        ratio_line("flat", m, "< 1% at 1M (exact method)" if m == "EXACT" else "(comparison)")
    for m in ("EXACT", "BVH", "SEED"):
        ratio_line("sphere", m, "< 5% at 1M (exact method)" if m == "EXACT" else "(comparison)")

    def largest_crumpled_with_exact(df, method):
        """The largest crumpled case run by `method` at df, and EXACT's row on it."""
        best = None
        for r in rows:
            if r["scene"] == "crumpled" and r["df"] == df and r["m"] == method:
                if best is None or r["triangles"] > best["triangles"]:
                    best = r
        if best is None:
            return None, None
        e = pick(rows, best["case"], df, "EXACT")
        if e is None or e["frame_ms"] <= 0:
            return None, None
        return best, e

    def bullet_ratio(df):
        best, e = largest_crumpled_with_exact(df, "BULLET")
        if best is None:
            return "-"
        return "%.2fx (Bullet %s + %s ms, EXACT %s + %s ms; %s tri, scale x%g)" % (
            best["frame_ms"] / e["frame_ms"], fmt_ms(best["refit_ms"]), fmt_ms(best["query_ms"]),
            fmt_ms(e["refit_ms"]), fmt_ms(e["query_ms"]), kilo(best["triangles"]), best["scale"])
    a, b = both(bullet_ratio)
    out.append("| crumpled, largest with Bullet: Bullet (refit + self-collision) / EXACT frame | %s | %s | >= 20x at 200k |" % (a, b))

    def ipc_ratio(df):
        best, e = largest_crumpled_with_exact(df, "IPCTK")
        if best is None:
            return "-"
        return "%.2fx (ipctk %s ms, EXACT %s ms; %s tri; ipctk misses %d EF it cannot report, %d other)" % (
            best["frame_ms"] / e["frame_ms"], fmt_ms(best["frame_ms"]), fmt_ms(e["frame_ms"]),
            kilo(best["triangles"]), best["miss_ef"], best["miss_vf"] + best["miss_ee"])
    a, b = both(ipc_ratio)
    out.append("| crumpled, largest with ipc-toolkit (1 thread): ipctk / EXACT frame | %s | %s | (reference) |" % (a, b))

    def ball(df):
        r = pick(rows, "cloth-ball-92", df, "EXACT")
        return "-" if r is None else "%s ms" % fmt_ms(r["frame_ms"])
    a, b = both(ball)
    out.append("| cloth-ball 92: EXACT frame | %s | %s | <= 20 ms, one core |" % (a, b))

    # Build time and bytes per triangle by size (d-independent).
    builds = [r for r in rows if r["m"] == "BVH" and r["df"] == "0.1"
              and r["scene"] in ("flat", "sphere", "crumpled")]
    for r in sorted(builds, key=lambda r: r["triangles"]):
        t = r["triangles"]
        bl = pick(rows, r["case"], "0.1", "BULLET")
        out.append("| build %s (%s tri): selfcol%s | %s ms%s, %.1f B/tri | | ~1 s at 1M; <= 64 B/tri |" % (
            r["case"], kilo(t), " / Bullet" if bl else "", fmt_ms(r["build_ms"]),
            (" / Bullet %s ms" % fmt_ms(bl["build_ms"])) if bl else "", r["bytes_per_tri"]))
    return "\n".join(out)


def table_exact_check(rows):
    """EXACT and BVH against EXHAUSTIVE wherever the exhaustive reference ran."""
    out = ["| d | cases with EXHAUSTIVE | EXACT misses / extras | BVH misses / extras | SEED misses | CONE misses |",
           "|---|---|---|---|---|---|"]
    for df in FACTORS:
        cs = [c for c in cases_in_order(rows) if pick(rows, c, df, "EXHAUSTIVE")]
        tot = {}
        for m in ("EXACT", "BVH", "SEED", "CONE"):
            mi = ex = 0
            for c in cs:
                r = pick(rows, c, df, m)
                if r:
                    mi += r["misses"]
                    ex += r["extras"]
            tot[m] = (mi, ex)
        out.append("| %s | %d | %d / %d | %d / %d | %d | %d |" % (
            df, len(cs), tot["EXACT"][0], tot["EXACT"][1], tot["BVH"][0], tot["BVH"][1],
            tot["SEED"][0], tot["CONE"][0]))
    return "\n".join(out)


def store_row_name(r):
    """STORE or STORE-FIRST, and the threads of the update when more than one."""
    threads = int(float(r.get("threads") or 1))
    return r["method"] + ("" if threads == 1 else " (%d threads)" % threads)


def table_store(rows):
    """Contact-store rows: selfcol_store_update per frame (one thread, and
    the STORE rows again on two), against the frame's EXACT refit and query
    (d = 0.1 x mean edge, one thread)."""
    if not rows:
        return ("(no contact-store rows in this run's CSV: `make bench` adds them; "
                "the numbers below the table were measured on their own)")
    out = ["| case | tri | row | updates | held VF+EE (VF / EE) | EF | regions | update ms (min-max) "
           "| ns / contact | new / kept / remnant / dropped | flipped | corrected | store MB "
           "| B / contact | EXACT refit + query ms | update / (refit + query + update) |",
           "|---" * 16 + "|"]
    for r in rows:
        frame = r["refit_ms"] + r["query_ms"] + r["store_update_ms"]
        out.append("| %s | %s | %s | %d | %.0f (%s / %s) | %s | %.0f | %s (%s-%s) | %.0f | "
                   "%.0f / %.0f / %.0f / %.0f | %.0f | %.0f | %.1f | %.0f | %s + %s | %.0f%% |" % (
                       r["case"], kilo(r["triangles"]), store_row_name(r), int(r["reps"]),
                       r["store_contacts"], fmt_int(r["vf"]), fmt_int(r["ee"]), fmt_int(r["ef"]),
                       r["store_regions"], fmt_ms(r["store_update_ms"]),
                       fmt_ms(r["store_update_min_ms"]), fmt_ms(r["store_update_max_ms"]),
                       r["store_ns_per_contact"], r["store_new"], r["store_kept"],
                       r["store_remnant"], r["store_dropped"], r["store_flipped"],
                       r["store_corrected"], r["struct_bytes"] / 1e6,
                       r["store_bytes_per_contact"], fmt_ms(r["refit_ms"]),
                       fmt_ms(r["query_ms"]), 100 * r["store_update_ms"] / frame if frame > 0 else 0))
    return "\n".join(out)


def load_sweep(path):
    """The first round of tools/bench/results/sweep.md (run_sweep.sh):
    {case: {row: median ms}}, selfcol's rows by mode and ipc-toolkit's
    stepsize and is_step_collision_free."""
    if not os.path.exists(path):
        return {}
    out, section, rnd = {}, None, None
    for line in open(path):
        if line.startswith("## Round "):
            rnd = line.split()[2].rstrip(":")
            section = "ipctk" if "ipc-toolkit" in line else "selfcol"
            continue
        if rnd != "1" or not line.startswith("| ") or line.startswith("| case"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        case = cells[0]
        ms = lambda c: float(c.split()[0])
        if section == "selfcol":
            out.setdefault(case, {})["selfcol " + cells[2]] = ms(cells[3])
        else:
            out.setdefault(case, {})["ipc-toolkit stepsize"] = ms(cells[2])
            out[case]["ipc-toolkit is_step_collision_free"] = ms(cells[4])
    return out


def chart_sweep(sweep, path):
    rows = ["selfcol EARLIEST, EXACT", "selfcol EARLIEST, BVH", "ipc-toolkit stepsize",
            "selfcol ALL, EXACT", "selfcol ALL, EXACT, 2 threads",
            "ipc-toolkit is_step_collision_free"]
    colors = ["#1f77b4", "#6baed6", "#d62728", "#aec7e8", "#98df8a", "#ff9896"]
    cases = list(sweep)
    fig, ax = plt.subplots(figsize=(10, 4.2))
    width = 0.8 / len(rows)
    for k, (row, color) in enumerate(zip(rows, colors)):
        xs = [i + (k - (len(rows) - 1) / 2) * width for i in range(len(cases))]
        ys = [sweep[c].get(row, float("nan")) for c in cases]
        ax.bar(xs, ys, width, label=row, color=color)
    ax.set_yscale("log")
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels(cases, fontsize=8)
    ax.set_ylabel("ms per step (median, log)", fontsize=8)
    ax.set_title("Continuous queries over one step, separation 0: the collision-free fraction "
                 "(selfcol EARLIEST, ipc-toolkit stepsize) and every pair (selfcol ALL)", fontsize=9)
    top = max(v for c in cases for v in sweep[c].values())
    ax.set_ylim(top=top * 20)  # room for the legend above the bars
    ax.legend(fontsize=7, ncol=3, loc="upper left")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def load_sequence(path):
    """Rows of selfcol-bench-sequence (tools/bench/bench_sequence.c):
    [(case, fresh mean ms, coherent mean ms, partial rebuilds)] in file order."""
    if not os.path.exists(path):
        return []
    fresh, out = {}, []
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["method"] == "FRESH":
                fresh[r["case"]] = float(r["frame_ms_mean"])
            elif r["case"] in fresh:
                out.append((r["case"], fresh[r["case"]], float(r["frame_ms_mean"]),
                            int(r.get("partial_rebuilds") or 0)))
    return out


def ms1(x):
    """Milliseconds with one decimal and thousands separators (the sequence table)."""
    return "{:,.1f}".format(x)


def table_sequence(paths):
    """The coherent-query table of docs/benchmarks.md from sequence CSVs
    (the default run's, then bench-full's when present), fresh and coherent
    rows paired by case."""
    rows = []
    for path in paths:
        if not os.path.exists(path):
            continue
        fresh = {}
        # The run a row comes from: `make bench` (sequence.csv) or `make
        # bench-full` (sequence-full.csv); both hold the 20k cases.
        run = "full" if os.path.basename(path) == "sequence-full.csv" else "default"
        with open(path) as f:
            for r in csv.DictReader(f):
                if r["method"] == "FRESH":
                    fresh[r["case"]] = r
                elif r["case"] in fresh:
                    rows.append((run, fresh[r["case"]], r))
    out = ["| run | case | triangles | fresh mean / median ms | coherent mean / median / max ms | "
           "mean ratio | rebuilds (partial), fresh frames | near pairs | sequence bytes / tri |",
           "|---|---|---|---|---|---|---|---|---|"]
    for run, f, c in rows:
        fm, cm = float(f["frame_ms_mean"]), float(c["frame_ms_mean"])
        near = float(c["near_pairs_mean"])
        near_text = ("%.2fM" % (near / 1e6) if near >= 1e6 else
                     "%.0fk" % (near / 1e3) if near >= 1e3 else "%.0f" % near)
        out.append("| %s | %s | %s | %s / %s | %s / %s / %s | %.1fx | %s (%s), %s of %s | %s | %.0f |" % (
            run, c["case"], "{:,}".format(int(c["triangles"])), ms1(fm), ms1(float(f["frame_ms_median"])),
            ms1(cm), ms1(float(c["frame_ms_median"])), ms1(float(c["frame_ms_max"])),
            fm / cm if cm > 0 else float("nan"), c["rebuilds"], c["partial_rebuilds"],
            c["fresh_frames"], c["frames"], near_text, float(c["bytes_per_tri"])))
    if not rows:
        out.append("| (no sequence rows) | | | | | | | |")
    return "\n".join(out)


def chart_sequence(seq, path):
    cases = [c for c, _, _, _ in seq]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    xs = range(len(cases))
    ax.bar([x - 0.2 for x in xs], [f for _, f, _, _ in seq], 0.4, label="fresh (refit + EXACT)",
           color="#d62728")
    ax.bar([x + 0.2 for x in xs], [c for _, _, c, _ in seq], 0.4,
           label="coherent (selfcol_sequence)", color="#1f77b4")
    for x, (_, f, c, partial) in zip(xs, seq):
        label = "%.1fx" % (f / c) + (" (%d partial)" % partial if partial else "")
        ax.text(x, max(f, c) * 1.15, label, ha="center", fontsize=7)
    ax.set_yscale("log")
    ax.set_ylim(top=max(f for _, f, _, _ in seq) * 4)  # room for the labels and legend
    ax.set_xticks(list(xs))
    ax.set_xticklabels(cases, fontsize=7)
    ax.set_ylabel("ms per frame (mean over the sequence, log)", fontsize=8)
    ax.set_title("The same self query frame after frame, d = 0.1 x mean edge, one thread: "
                 "records equal on every frame", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def load_step_trace(path):
    """Per step of the Bullet ribbon (selfcol-bullet-bench --trace): for each
    mode, the median over the runs of each step's times (ms)."""
    if not os.path.exists(path):
        return None
    per = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            key = (r["mode"], int(r["step"]))
            cols = ("step_ms", "detect_ms", "response_ms", "store_ms")
            per.setdefault(key, []).append([float(r[c]) if r[c] != "" else 0.0 for c in cols])
    out = {}
    for (mode, step), runs in per.items():
        columns = list(zip(*runs))  # each column over the runs
        out.setdefault(mode, {})[step] = [sorted(c)[len(c) // 2] for c in columns]
    return out


def chart_step_trace(trace, path, size, window):
    """Stacked per-step times of the selfcol run (Bullet's own part of the
    step, selfcol's query, store, response) against the step without
    self-collision, medians over the runs, binned by 12 steps."""
    sel, off = trace.get("selfcol"), trace.get("off")
    if not sel or not off:
        return False
    steps = sorted(set(sel) & set(off))
    binned = []
    for i in range(0, len(steps), 12):
        chunk = steps[i:i + 12]
        med = lambda vals: sorted(vals)[len(vals) // 2]  # noqa: E731
        step, detect, response, store = (med([sel[s][k] for s in chunk]) for k in range(4))
        binned.append((chunk[0], med([off[s][0] for s in chunk]),
                       max(step - detect - response, 0.0), max(detect - store, 0.0), store,
                       response))
    x = [b[0] for b in binned]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.stackplot(x, [b[2] for b in binned], [b[3] for b in binned], [b[4] for b in binned],
                 [b[5] for b in binned],
                 labels=["Bullet's own step (with selfcol)", "selfcol: positions, refit, query",
                         "selfcol: contact store", "selfcol: response"],
                 colors=["#bbbbbb", "#1f77b4", "#ff7f0e", "#2ca02c"], alpha=0.85)
    ax.plot(x, [b[1] for b in binned], color="black", lw=1.2, label="step without self-collision")
    ax.axvspan(x[-1] - window, x[-1] + 12, color="#d62728", alpha=0.06,
               label="measured window (the last %d steps)" % window)
    ax.set_xlabel("step (1/240 s each; the ends are driven together over all of them)",
                  fontsize=8)
    ax.set_ylabel("ms per step (median of runs, 12-step bins)", fontsize=8)
    ax.set_title("Bullet ribbon %s, one thread: where each world step's time goes" % size,
                 fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return True


def chart_fast_trace(results, path):
    """The fast-compression ribbon with the continuous option
    (bullet_step_fast_trace.csv): each step's time stacked (Bullet's own
    part, selfcol's detection, response, continuous passes), 8-step bins,
    against the ordinary 20k ribbon's discrete step median and 3x it (issue
    39's target), both from bullet_step_fast.csv."""
    trace = os.path.join(results, "bullet_step_fast_trace.csv")
    rows_path = os.path.join(results, "bullet_step_fast.csv")
    if not os.path.exists(trace) or not os.path.exists(rows_path):
        return False
    with open(rows_path) as f:
        ordinary = [r for r in csv.DictReader(f) if r["mode"] == "selfcol"]
    with open(trace) as f:
        steps = [r for r in csv.DictReader(f) if r["mode"] == "selfcol-continuous"]
    if not ordinary or not steps:
        return False
    reference = float(ordinary[0]["step_median_ms"])
    med = lambda vals: sorted(vals)[len(vals) // 2]  # noqa: E731
    binned = []
    for i in range(0, len(steps), 8):
        chunk = steps[i:i + 8]
        col = lambda c: med([float(r[c]) for r in chunk])  # noqa: E731,B023
        step, detect, response, cont = (col(c) for c in ("step_ms", "detect_ms", "response_ms",
                                                           "continuous_ms"))
        binned.append((int(chunk[0]["step"]), max(step - detect - response - cont, 0.0), detect,
                       response, cont, col("continuous_passes")))
    x = [b[0] for b in binned]
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.stackplot(x, [b[1] for b in binned], [b[2] for b in binned], [b[3] for b in binned],
                 [b[4] for b in binned],
                 labels=["Bullet's own step", "selfcol: positions, refit, query, store",
                         "selfcol: response", "selfcol: continuous passes"],
                 colors=["#bbbbbb", "#1f77b4", "#2ca02c", "#9467bd"], alpha=0.85)
    ax.axhline(reference, color="black", lw=1.2,
               label="ordinary 20k ribbon, discrete selfcol step (median %.1f ms)" % reference)
    ax.axhline(3 * reference, color="#d62728", lw=1.0, ls="--", label="3x that (the target)")
    ax2 = ax.twinx()
    ax2.plot(x, [b[5] for b in binned], color="#8c564b", lw=0.9, label="continuous passes")
    ax2.set_ylabel("continuous passes per step", fontsize=8)
    ax.set_xlabel("step (1/240 s each; the ends are driven together over the first 300)",
                  fontsize=8)
    ax.set_ylabel("ms per step (8-step bins, medians)", fontsize=8)
    ax.set_title("Fast-compression ribbon (19k faces), continuous option, one thread", fontsize=9)
    lines, labels = ax.get_legend_handles_labels()
    lines2, labels2 = ax2.get_legend_handles_labels()
    ax.legend(lines + lines2, labels + labels2, fontsize=7, loc="upper left")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return True


def replace_block(text, name, content):
    pat = re.compile(r"(<!-- generated:%s -->\n).*?(<!-- /generated:%s -->)" % (name, name), re.S)
    if not pat.search(text):
        return text + "\n<!-- generated:%s -->\n%s\n<!-- /generated:%s -->\n" % (name, content, name)
    return pat.sub(lambda m: m.group(1) + content + "\n" + m.group(2), text)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", default=".")
    ap.add_argument("--subset", default="default")
    ap.add_argument("--results", default=None)
    ap.add_argument("--docs", default=None)
    ap.add_argument("--check", action="store_true",
                    help="draw nothing, write nothing: fail when a generated table of "
                         "benchmarks.md differs from what the committed results give")
    a = ap.parse_args()
    results = a.results or os.path.join(a.root, "tools", "bench", "results")
    docs = a.docs or os.path.join(a.root, "docs")
    rows, meta, store = load(results, a.subset)
    if not rows:
        print("plot: no rows in %s/%s.csv" % (results, a.subset), file=sys.stderr)
        return 1
    if a.check:
        return check_tables(a, results, docs, rows, meta, store)
    if plt is None:
        print("plot: matplotlib is missing (tools/plot/plot.sh installs it)", file=sys.stderr)
        return 1
    os.makedirs(docs, exist_ok=True)
    note = ("Generated scenes have edges ~1 unit, far above Bullet's ~1.8 cm dead zone: no scaling "
            "(real frames: xN in the title); *-raw: a 1 m cloth left inside it.")
    written = []
    for df in FACTORS:
        tag = df.replace(".", "")
        for name, fn in (("speed-accuracy", lambda p: chart_speed_accuracy(rows, df, p, note)),
                         ("scaling", lambda p: chart_scaling(rows, df, p)),
                         ("culling", lambda p: chart_culling(rows, df, p))):
            p = os.path.join(docs, "bench-%s-d%s.png" % (name, tag))
            fn(p)
            written.append(p)
    sweep = load_sweep(os.path.join(results, "sweep.md"))
    if sweep:
        p = os.path.join(docs, "bench-sweep.png")
        chart_sweep(sweep, p)
        written.append(p)
    seq = load_sequence(os.path.join(
        results, "sequence.csv" if a.subset == "default" else "sequence-%s.csv" % a.subset))
    if seq:
        p = os.path.join(docs, "bench-sequence.png")
        chart_sequence(seq, p)
        written.append(p)
    trace = load_step_trace(os.path.join(results, "bullet_step_20k_trace.csv"))
    if trace:
        p = os.path.join(docs, "bench-bullet-step.png")
        if chart_step_trace(trace, p, "20k", 360):
            written.append(p)
    p = os.path.join(docs, "bench-bullet-fast.png")
    if chart_fast_trace(results, p):
        written.append(p)
    md = os.path.join(docs, "benchmarks.md")
    text = open(md).read() if os.path.exists(md) else "# Benchmarks\n"
    text = generated_tables(text, a, results, rows, meta, store)
    with open(md, "w") as f:
        f.write(text)
    for p in written + [md]:
        print("plot: wrote %s" % os.path.relpath(p, a.root))
    return 0


def check_tables(a, results, docs, rows, meta, store):
    """--check: the generated blocks of benchmarks.md against the results."""
    md = os.path.join(docs, "benchmarks.md")
    text = open(md).read()
    want = generated_tables(text, a, results, rows, meta, store)
    if want == text:
        print("plot: the generated tables of %s hold the committed results" % md)
        return 0
    names = re.findall(r"<!-- generated:([a-z0-9-]+) -->", want)
    for name in names:
        pat = re.compile(r"<!-- generated:%s -->\n(.*?)<!-- /generated:%s -->" % (name, name), re.S)
        old, new = pat.search(text), pat.search(want)
        if old is None or new is None or old.group(1) != new.group(1):
            print("plot: %s: block '%s' is not what the committed results give "
                  "(run make plot and commit)" % (md, name), file=sys.stderr)
    return 1


def generated_tables(text, a, results, rows, meta, store):
    text = replace_block(text, "machine", table_machine(meta))
    text = replace_block(text, "headlines", table_headlines(rows))
    text = replace_block(text, "exact-check", table_exact_check(rows))
    text = replace_block(text, "store", table_store(store))
    text = replace_block(text, "sequence", table_sequence(
        [os.path.join(results, "sequence.csv"), os.path.join(results, "sequence-full.csv")]))
    for df in FACTORS:
        text = replace_block(text, "cases-d%s" % df.replace(".", ""), table_cases(rows, df))
    # The full subset (make bench-full) is long; when its results exist, its
    # headline numbers (1M triangles, Bullet at 200k) are shown too.
    if a.subset != "full" and os.path.exists(os.path.join(results, "full.csv")):
        frows, fmeta, _ = load(results, "full")
        text = replace_block(text, "full-machine", table_machine(fmeta))
        text = replace_block(text, "full-headlines", table_headlines(frows))
        text = replace_block(text, "full-exact-check", table_exact_check(frows))
    return text


if __name__ == "__main__":
    sys.exit(main())
