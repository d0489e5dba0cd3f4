#!/usr/bin/env python3
"""Plots of a `shellflow bench` folder (run by `shellflow bench` itself, or by hand):

  BENCH_DIR/plots/<measure>_vs_time.png  each error against wall time on log-log axes, one
      series per value of the axes that are not refined, the Pareto front (no other run both
      cheaper and more accurate) dashed, the observed order p (error ~ h^p, along the axis
      whose spacing the spec gives) in the legend;
  BENCH_DIR/plots/stability.png  for a two-axis sweep: each run's outcome (completed, guard
      stopped, non-finite, crashed, failed) coloured, with energy_change (the energy gained
      over the run over its largest kinetic energy; the first error without energies)
      written in.

Usage: plot_bench.py BENCH_DIR. Needs matplotlib (Debian: python3-matplotlib).
"""

import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUTCOME_COLOURS = {
    "completed": "#4caf50",
    "guard_stopped": "#ff9800",
    "non_finite": "#e53935",
    "crashed": "#8e24aa",
    "failed": "#9e9e9e",
}


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def slope(xs, ys):
    """Least-squares slope of log y against log x over positive finite pairs."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys)
           if x > 0 and y > 0 and math.isfinite(x) and math.isfinite(y)]
    if len(pts) < 2:
        return float("nan")
    n = len(pts)
    sx = sum(p[0] for p in pts)
    sy = sum(p[1] for p in pts)
    sxx = sum(p[0] ** 2 for p in pts)
    sxy = sum(p[0] * p[1] for p in pts)
    d = n * sxx - sx * sx
    return (n * sxy - sx * sy) / d if abs(d) > 1e-300 else float("nan")


def pareto(points):
    """The runs no other run beats in both wall time and error, cheapest first."""
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def error_plots(bench, rows, out_dir):
    axes = bench["axes"]
    refined = [i for i, a in enumerate(axes) if a["spacing"] != "none"]
    written = []
    for measure in bench["measures"]:
        label = measure["label"]
        groups = {}
        for r in rows:
            e, t = number(r.get(label)), number(r["run_s"])
            if r["status"] != "completed" or not (e > 0) or not (t > 0):
                continue
            key = ", ".join(f"{a['label']} = {r[a['label']]}" for i, a in enumerate(axes)
                            if i not in refined[:1])
            groups.setdefault(key, []).append(r)
        if not groups:
            continue
        fig, ax = plt.subplots(figsize=(5.2, 3.8), dpi=100)
        everything = []
        for key, runs in groups.items():  # in run order: the sweep's own order of values
            t = [number(r["run_s"]) for r in runs]
            e = [number(r[label]) for r in runs]
            everything += list(zip(t, e))
            legend = key or "runs"
            if refined:
                a = axes[refined[0]]
                v = [number(r[a["label"]]) for r in runs]
                h = [1.0 / x if a["spacing"] == "inverse" else x for x in v]
                p = slope(h, e)
                if math.isfinite(p):
                    legend += f" (p = {p:.2f} along {a['label']})"
            else:
                s = slope(t, e)
                if math.isfinite(s):
                    legend += f" (error ~ time^{s:.2f})"
            ax.plot(t, e, "o", label=legend)
        front = pareto(everything)
        if len(front) > 1:
            ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=1,
                    label="Pareto front")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the run [s] (run.json)")
        ax.set_ylabel(f"{label} ({measure['measure']})")
        ax.set_title(f"{bench['bench']}: {label}", fontsize=10)
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        path = os.path.join(out_dir, f"{label}_vs_time.png")
        fig.savefig(path)
        plt.close(fig)
        written.append(path)
    return written


def stability_map(bench, rows, out_dir):
    axes = bench["axes"]
    if len(axes) != 2:
        return []
    xs = [json.dumps(v) if not isinstance(v, str) else v for v in axes[1]["values"]]
    ys = [json.dumps(v) if not isinstance(v, str) else v for v in axes[0]["values"]]
    fig, ax = plt.subplots(figsize=(max(3.0, 1.4 + 0.8 * len(xs)) + 1.6, 1.6 + 0.45 * len(ys)),
                           dpi=100)
    seen = set()
    for r in rows:
        x = xs.index(r[axes[1]["label"]]) if r[axes[1]["label"]] in xs else None
        y = ys.index(r[axes[0]["label"]]) if r[axes[0]["label"]] in ys else None
        if x is None or y is None:
            continue
        colour = OUTCOME_COLOURS.get(r["status"], "#9e9e9e")
        ax.add_patch(plt.Rectangle((x - 0.5, y - 0.5), 1, 1, color=colour,
                                   label=r["status"] if r["status"] not in seen else None))
        seen.add(r["status"])
        energy = number(r.get("energy_change"))
        first = number(r.get(bench["measures"][0]["label"])) if bench["measures"] else float("nan")
        text = f"{energy:+.2f}" if math.isfinite(energy) else (
            f"{first:.1e}" if math.isfinite(first) else "")
        ax.text(x, y, text, ha="center", va="center", fontsize=7)
    ax.set_xlim(-0.5, len(xs) - 0.5)
    ax.set_ylim(-0.5, len(ys) - 0.5)
    ax.set_xticks(range(len(xs)))
    ax.set_xticklabels(xs, fontsize=7)
    ax.set_yticks(range(len(ys)))
    ax.set_yticklabels(ys, fontsize=7)
    ax.set_xlabel(axes[1]["pointer"])
    ax.set_ylabel(axes[0]["pointer"])
    ax.set_title(f"{bench['bench']}\noutcome; energy change over the largest kinetic energy",
                 fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    path = os.path.join(out_dir, "stability.png")
    fig.savefig(path)
    plt.close(fig)
    return [path]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    bench_dir = sys.argv[1]
    with open(os.path.join(bench_dir, "bench.json")) as f:
        bench = json.load(f)
    with open(os.path.join(bench_dir, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    out_dir = os.path.join(bench_dir, "plots")
    os.makedirs(out_dir, exist_ok=True)
    written = error_plots(bench, rows, out_dir) + stability_map(bench, rows, out_dir)
    for path in written:
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
