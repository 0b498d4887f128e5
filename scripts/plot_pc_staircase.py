#!/usr/bin/python3
"""Draws the capillary-pressure / gas-saturation curve of the parallel-slit ramp
(tests/validation/test_fluid_pc_staircase_long.cpp writes <build>/fluid_pc_staircase_<tag>.csv)
against the closed-form staircase S_gas(Pc) = sum over the slits with 2 gamma cos(theta) / w_k < Pc
of w_k / (w + 2w + 3w). Several CSV files (e.g. the full and the half ramp rate) go on one plot.

    /usr/bin/python3 scripts/plot_pc_staircase.py OUT.png build/fluid_pc_staircase_slow.csv [more.csv]

Needs numpy and matplotlib (Debian's python3-matplotlib).
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    thresholds = None
    with open(path) as f:
        first = f.readline()
        if "Pc_k =" in first:
            thresholds = [float(v) for v in first.split("Pc_k =")[1].split()[:3]]
    d = np.loadtxt(path, delimiter=",", comments="#")
    return d, thresholds


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(1)
    out = sys.argv[1]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5))
    thresholds = None
    for path in sys.argv[2:]:
        d, th = read(path)
        thresholds = thresholds or th
        label = path.rsplit("/", 1)[-1].replace(".csv", "")
        ax.plot(d[:, 6], d[:, 2], lw=1.2, label=f"SPH, {label}")
        for k, name in enumerate(["w", "2w", "3w"]):
            bx.plot(d[:, 2], d[:, 3 + k], lw=1, label=f"{name}, {label}")
    if thresholds:
        pw, p2, p3 = thresholds
        pmax = ax.get_ylim()[1]
        # staircase: S = 0 below Pc_3w, 1/2 (3w of 6w) up to Pc_2w, 5/6 up to Pc_w, 1 above
        s = [0, 0, 0.5, 0.5, 5 / 6, 5 / 6, 1, 1]
        p = [0, p3, p3, p2, p2, pw, pw, pmax]
        ax.plot(s, p, "k--", lw=1.5, label="closed form (Young-Laplace staircase)")
        for v in thresholds:
            bx.axvline(v, color="k", ls=":", lw=0.8)
    ax.set_xlabel("gas saturation of the slits S_gas")
    ax.set_ylabel("capillary pressure Pc = rho f Lx + 2 gamma cos(theta) / H (Pa)")
    ax.legend(fontsize=8)
    ax.set_title("Pc-S: parallel slits w, 2w, 3w")
    bx.set_xlabel("Pc (Pa)")
    bx.set_ylabel("gas saturation of each slit")
    bx.legend(fontsize=7)
    bx.set_title("per slit (dotted: Young-Laplace thresholds)")
    fig.tight_layout()
    fig.savefig(out, dpi=100)


if __name__ == "__main__":
    main()
