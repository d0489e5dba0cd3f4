#!/usr/bin/env python3
"""The README's dam-break figure: the simulated surge front Z = x/a against T = t sqrt(2g/a)
beside Martin and Moyce's (1952) Table 2 (tests/data/martin_moyce_1952.csv).

The front history comes from the test WaterValidation.DamBreakFrontSpeedFollowsMartinAndMoyce
(the scene of configs/verify/water_dam_break.json at 64 cells across), which writes it as CSV
when SHELLFLOW_DAM_BREAK_CSV names a file. By default this script runs that test from the
build folder; --csv plots a history written before.

usage: python3 scripts/plot_dam_break.py [--build build] [--csv FILE] [--out PNG]
"""

import argparse
import csv
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TEST = "tests/plugins/grid_fluid/test_water_validation_test"
FILTER = "Layouts/WaterValidation.DamBreakFrontSpeedFollowsMartinAndMoyce/nodes"


def read_rows(path):
    """Rows of a CSV with a header, '#' lines skipped, as dicts of floats."""
    with open(path) as f:
        lines = [line for line in f if line.strip() and not line.startswith("#")]
    return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(lines)]


def interpolate(xs, ys, x):
    for i in range(1, len(xs)):
        if x <= xs[i]:
            return ys[i - 1] + (ys[i] - ys[i - 1]) * (x - xs[i - 1]) / (xs[i] - xs[i - 1])
    return ys[-1]


def first_reach(ts, zs, z):
    for i in range(1, len(zs)):
        if zs[i] >= z:
            return ts[i - 1] + (ts[i] - ts[i - 1]) * (z - zs[i - 1]) / (zs[i] - zs[i - 1])
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder")
    parser.add_argument("--csv", help="front history written by the test (skips the run)")
    parser.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "dam_break_front.png"))
    args = parser.parse_args()

    history = args.csv
    if history is None:
        history = os.path.join(ROOT, "out", "dam_break_front.csv")
        os.makedirs(os.path.dirname(history), exist_ok=True)
        env = dict(os.environ, SHELLFLOW_DAM_BREAK_CSV=history)
        if os.path.exists(history):
            os.remove(history)
        subprocess.run([os.path.join(args.build, TEST), "--gtest_filter=" + FILTER], env=env,
                       check=False)
        if not os.path.exists(history):
            sys.exit(f"{TEST} in {args.build} wrote no {history}: build it first")
    sim = read_rows(history)
    data = read_rows(os.path.join(ROOT, "tests", "data", "martin_moyce_1952.csv"))
    ts = [r["T"] for r in sim]
    zs = [r["Z"] for r in sim]

    # The same figures as the test: the front error over T in [1.5, 3], and how much earlier
    # the simulated front reaches each measured Z (before T = 1.5, and over [1.5, 3]).
    errors = [(interpolate(ts, zs, d["T"]) - d["Z"]) / d["Z"] for d in data
              if 1.5 <= d["T"] <= ts[-1]]
    early = [d["T"] - first_reach(ts, zs, d["Z"]) for d in data
             if d["T"] < 1.5 and first_reach(ts, zs, d["Z"]) is not None]
    lead = [d["T"] - first_reach(ts, zs, d["Z"]) for d in data
            if 1.5 <= d["T"] <= ts[-1] and first_reach(ts, zs, d["Z"]) is not None]
    worst = max(errors, key=abs)
    mean_lead = sum(lead) / len(lead)
    # The experiment's release delay, measured on their points before T = 1.5 alone (as the
    # test DamBreakFrontFollowsMartinAndMoyceOnceTheirReleaseDelayIsOut does), and the front
    # over [1.5, 3] read that much later.
    delay = sum(early) / len(early)
    delayed = [(interpolate(ts, zs, d["T"] - delay) - d["Z"]) / d["Z"] for d in data
               if 1.5 <= d["T"] <= ts[-1]]
    print(f"front error over T in [1.5, 3]: {100 * min(errors):+.1f}% to {100 * max(errors):+.1f}%")
    print("before T = 1.5 the simulation reaches their Z earlier by "
          + ", ".join(f"{e:+.2f}" for e in early) + f" in T (mean {sum(early) / len(early):+.3f})")
    print(f"over T in [1.5, 3] it leads by {min(lead):.2f} to {max(lead):.2f} (mean {mean_lead:.3f})")
    print(f"their release delay (before T = 1.5) {delay:.3f} taken out: the front over T in "
          f"[1.5, 3] {100 * min(delayed):+.1f}% to {100 * max(delayed):+.1f}%")

    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    ax.axvspan(1.5, 3.0, color="0.93", zorder=0)
    ax.plot(ts, zs, "-", color="tab:blue", lw=1.8, label="shellflow, 64×40×4 cells, level set")
    ax.plot([t + delay for t in ts], zs, "--", color="tab:blue", lw=1.0,
            label=f"the same {delay:.2f} later (their release delay, fitted before T = 1.5)")
    band = [d for d in data if 1.5 <= d["T"] <= 3.0]
    ax.errorbar([d["T"] for d in band], [d["Z"] for d in band],
                yerr=[0.1 * d["Z"] for d in band], fmt="none", ecolor="0.55", capsize=2,
                label="±10% over T ∈ [1.5, 3] (issue 11)")
    ax.plot([d["T"] for d in data], [d["Z"] for d in data], "o", color="black", ms=5,
            label="Martin and Moyce 1952, Table 2")
    ax.set_xlabel(r"$T = t\,\sqrt{2g/a}$")
    ax.set_ylabel(r"$Z = x_{\mathrm{front}}/a$")
    ax.set_xlim(0.0, 3.4)
    ax.set_ylim(1.0, 4.2)
    ax.set_title(f"Dam break, column a × 2a, over T ∈ [1.5, 3]: front {100 * min(errors):+.0f} "
                 f"to {100 * max(errors):+.0f}%,\n{100 * min(delayed):+.0f} to "
                 f"{100 * max(delayed):+.0f}% with their release delay ({delay:.2f} in T) out",
                 fontsize=10)
    ax.grid(True, lw=0.4, color="0.85")
    ax.legend(loc="upper left", fontsize=8, frameon=False)
    fig.tight_layout()
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    fig.savefig(args.out)
    print(f"wrote {os.path.relpath(args.out, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
