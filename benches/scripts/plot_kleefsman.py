#!/usr/bin/env python3
"""The gauges P1 and P3 of SPHERIC test 2 (Kleefsman et al. 2005) from dam-break runs against
the measured record, one panel per gauge, for docs/validation.md.

    python3 benches/scripts/plot_kleefsman.py OUT.png LABEL=RUN_DIR [LABEL=RUN_DIR ...]

Each RUN_DIR is a dam-break output folder of data/scenes/kleefsman-obstacle.ron (its
diagnostics.csv has the columns time, p_P1, p_P3). Pressures as p/(rho g H) against
t sqrt(g/H), H = 0.55 m, rho = 1000 kg/m3, g = 9.81 m/s2, as the app compares them.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DEPTH = 0.55
TIME_SCALE = math.sqrt(9.81 / DEPTH)
PRESSURE_SCALE = 1000.0 * 9.81 * DEPTH
RECORD = os.path.join(
    os.path.dirname(__file__), "..", "..", "data", "validation", "kleefsman-2005-record-p1-p3.csv"
)


def columns(path, names):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [[float(r[n]) for r in rows] for n in names]


def main():
    out, runs = sys.argv[1], [a.rsplit("=", 1) for a in sys.argv[2:]]
    t, p1, p3 = columns(RECORD, ["t_s", "p1_pa", "p3_pa"])
    measured = {"P1": p1, "P3": p3}
    fig, axes = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for ax, gauge, height in zip(axes, ["P1", "P3"], [21, 101]):
        ax.plot([s * TIME_SCALE for s in t], [p / PRESSURE_SCALE for p in measured[gauge]],
                color="black", lw=1.2, label="Kleefsman et al. (2005), record")
        for label, run in runs:
            time, p = columns(os.path.join(run, "diagnostics.csv"), ["time", "p_" + gauge])
            p = [0.0 if math.isnan(v) else v / PRESSURE_SCALE for v in p]
            ax.plot([s * TIME_SCALE for s in time], p, lw=0.8, label=label)
        ax.axvspan(3.0, 5.5, color="0.9", zorder=0)
        ax.set_ylim(-0.5, 3.0)
        ax.set_xlim(0.0, 6.0)
        ax.set_ylabel("p / (ρ g H)")
        ax.set_title(f"{gauge}, {height} mm above the floor (grey: the plateau compared)")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("t √(g/H)")
    fig.suptitle("SPHERIC test 2: pressure on the obstacle's front face")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
