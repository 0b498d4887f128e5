#!/usr/bin/python3
"""Renders particle dumps of the wetting tests (x y material per line; 0 liquid, 1 gas, 2 wall,
3 lid) to one PNG with a panel per dump. Usage: plot_wetting_dumps.py OUT.png DUMP[:TITLE] ..."""
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

out, items = sys.argv[1], sys.argv[2:]
cols = min(len(items), 3)
rows = (len(items) + cols - 1) // cols
fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 4 * rows), squeeze=False)
colour = {0: "#1f3b73", 1: "#cfe3f7", 2: "#7f7f7f", 3: "#d9d9d9"}
for ax, item in zip(axes.flat, items):
    path, _, title = item.partition(":")
    d = np.loadtxt(path)
    x, y, m = d[:, 0] * 1e3, d[:, 1] * 1e3, d[:, 2].astype(int)
    for k, c in colour.items():
        s = m == k
        ax.scatter(x[s], y[s], s=4, c=c, marker="s", linewidths=0)
    ax.set_aspect("equal")
    ax.set_title(title or path, fontsize=9)
    ax.set_xlabel("x (mm)")
for ax in list(axes.flat)[len(items):]:
    ax.axis("off")
fig.tight_layout()
fig.savefig(out, dpi=110)
