#!/usr/bin/env python3
"""The gauges P1 and P3 and the water levels H2 and H4 of SPHERIC test 2 (Kleefsman et al.
2005) from dam-break runs against the measured record, one panel per gauge, for
docs/validation.md.

    python3 benches/scripts/plot_kleefsman.py OUT.png LABEL=RUN_DIR [LABEL=RUN_DIR ...]

Each RUN_DIR is a dam-break output folder of data/scenes/kleefsman-obstacle.ron (its
diagnostics.csv has the columns time, p_P1, p_P3, h_H2, h_H4). Pressures as p/(rho g H),
levels as h/H, against t sqrt(g/H), H = 0.55 m, rho = 1000 kg/m3, g = 9.81 m/s2, as the app
compares them; a dry gauge (no particle near, NaN) reads 0.
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
VALIDATION = os.path.join(os.path.dirname(__file__), "..", "..", "data", "validation")
RECORD = os.path.join(VALIDATION, "kleefsman-2005-record-p1-p3.csv")
LEVELS = os.path.join(VALIDATION, "kleefsman-2005-record-h2-h4.csv")


def columns(path, names):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [[float(r[n]) for r in rows] for n in names]


def main():
    out, runs = sys.argv[1], [a.rsplit("=", 1) for a in sys.argv[2:]]
    t, p1, p3 = columns(RECORD, ["t_s", "p1_pa", "p3_pa"])
    t_levels, h2, h4 = columns(LEVELS, ["t_s", "h2_m", "h4_m"])
    panels = [
        ("p_P1", "P1, 21 mm above the floor", t, p1, PRESSURE_SCALE, "p / (ρ g H)", (-0.5, 3.0)),
        ("p_P3", "P3, 101 mm above the floor", t, p3, PRESSURE_SCALE, "p / (ρ g H)", (-0.5, 3.0)),
        ("h_H2", "H2, water level between the column and the box", t_levels, h2, DEPTH, "h / H", (0.0, 1.0)),
        ("h_H4", "H4, water level in the column", t_levels, h4, DEPTH, "h / H", (0.0, 1.1)),
    ]
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 12), sharex=True)
    for ax, (column, title, t_ref, ref, scale, label, limits) in zip(axes, panels):
        ax.plot([s * TIME_SCALE for s in t_ref], [v / scale for v in ref],
                color="black", lw=1.2, label="Kleefsman et al. (2005), record")
        for index, (name, run) in enumerate(runs):
            path = os.path.join(run, "diagnostics.csv")
            with open(path) as f:
                if column not in f.readline().strip().split(","):
                    continue  # a run from before the scene had this gauge
            time, values = columns(path, ["time", column])
            values = [0.0 if math.isnan(v) else v / scale for v in values]
            ax.plot([s * TIME_SCALE for s in time], values, lw=0.8, label=name, color=f"C{index}")
        if column.startswith("p_"):
            ax.axvspan(3.0, 5.5, color="0.9", zorder=0)
            title += " (grey: the plateau compared)"
        ax.set_ylim(*limits)
        ax.set_xlim(0.0, 6.0)
        ax.set_ylabel(label)
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("t √(g/H)")
    fig.suptitle("SPHERIC test 2: pressure on the box's front face and water levels")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
