#!/usr/bin/env python3
"""Plots a run's metrics.csv columns against time: `shellflow plot RUN_DIR [COLUMNS...]`.

Writes RUN_DIR/plots/<column>.png, one figure per column, with the simulated time on the x
axis. Without COLUMNS it draws the columns that say how a run went: energies, volumes and
masses, solver iterations and maximum speeds (whichever the run wrote). Exit code 1, with
a message that says what to change, for a missing run folder, a missing metrics.csv or an
unknown column (the available ones are listed).
"""
import argparse
import csv
import math
import os
import re
import sys

DEFAULT_PATTERNS = ("energy", "volume", "mass", "iterations", "max_speed", "speed_max")
NOT_PLOTTED = ("step", "frame", "time")


def fail(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(1)


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def main():
    parser = argparse.ArgumentParser(prog="shellflow plot", description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", help="the run's output folder, as out/<scene name>")
    parser.add_argument("columns", nargs="*", help="metrics.csv columns (default: energies, "
                        "volumes, masses, iterations, maximum speeds)")
    parser.add_argument("--out", help="folder for the PNGs (default: RUN_DIR/plots)")
    args = parser.parse_args()

    if not os.path.isdir(args.run_dir):
        fail(f"run folder not found: {args.run_dir} (give the folder a run wrote, as out/<scene name>)")
    metrics = os.path.join(args.run_dir, "metrics.csv")
    if not os.path.isfile(metrics):
        fail(f"{args.run_dir} has no metrics.csv: is it a shellflow run folder?")
    with open(metrics, newline="") as f:
        reader = csv.DictReader(f)
        available = list(reader.fieldnames or [])
        rows = list(reader)
    if "time" not in available or not rows:
        fail(f"{metrics} has no rows or no 'time' column")
    plottable = [c for c in available if c not in NOT_PLOTTED]

    if args.columns:
        unknown = [c for c in args.columns if c not in available or c in NOT_PLOTTED]
        if unknown:
            fail(f"no column {', '.join(repr(c) for c in unknown)} in {metrics}; "
                 f"available: {' '.join(plottable)}")
        columns = args.columns
    else:
        columns = [c for c in plottable if any(p in c for p in DEFAULT_PATTERNS)]
        if not columns:
            fail(f"none of the default columns ({', '.join(DEFAULT_PATTERNS)}) in {metrics}; "
                 f"name some: {' '.join(plottable)}")

    try:
        import matplotlib
        matplotlib.use("Agg")  # files only, no display
        import matplotlib.pyplot as plt
    except ImportError:
        fail("python3 cannot import matplotlib: install python3-matplotlib (scripts/setup.sh does)")

    out_dir = args.out or os.path.join(args.run_dir, "plots")
    os.makedirs(out_dir, exist_ok=True)
    time = [number(r["time"]) for r in rows]
    scene = os.path.basename(os.path.normpath(args.run_dir))
    for column in columns:
        values = [number(r[column]) for r in rows]
        fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
        ax.plot(time, values, lw=1.2)
        ax.set_xlabel("time [s]")
        ax.set_ylabel(column)
        ax.set_title(f"{scene}: {column}")
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        file = os.path.join(out_dir, re.sub(r"[^A-Za-z0-9_.-]", "_", column) + ".png")
        fig.savefig(file)
        plt.close(fig)
        print(file)


if __name__ == "__main__":
    main()
