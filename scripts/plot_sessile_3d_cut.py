#!/usr/bin/python3
"""Renders the mid-plane cut (y = the cell's centre, one lattice layer) of 3D sessile-drop dumps
(x y z material per line; 0 liquid, 1 gas, 2 wall; tests/validation/fluid_wetting_3d_case.hpp)
to one PNG with a panel per dump, with the circle of the prescribed angle's spherical cap of the
drop's volume drawn for comparison. Usage:
    plot_sessile_3d_cut.py OUT.png DUMP:THETA[:TITLE] ...
THETA is the prescribed angle in degrees (the reference cap: the drop's liquid volume, the wall
surface half-way between the wall's top layer and the fluid's lowest)."""
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

out, items = sys.argv[1], sys.argv[2:]
cols = min(len(items), 3)
rows = (len(items) + cols - 1) // cols
fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.6 * rows), squeeze=False)
colour = {0: "#1f3b73", 1: "#cfe3f7", 2: "#7f7f7f"}
for ax, item in zip(axes.flat, items):
    parts = item.split(":")
    path, theta = parts[0], float(parts[1])
    title = parts[2] if len(parts) > 2 else path
    d = np.loadtxt(path)
    x, y, z, m = d[:, 0], d[:, 1], d[:, 2], d[:, 3].astype(int)
    wz = np.unique(np.round(z[m == 2], 9))  # the wall does not move: its layers give dx
    dx = float(np.min(np.diff(wz))) if len(wz) > 1 else float(np.min(np.diff(np.unique(np.round(y[m == 2], 9)))))
    wy = np.unique(np.round(y[m == 2], 9))
    layer = wy[np.argmin(np.abs(wy - np.mean(y[m == 0])))]  # the lattice layer nearest the drop's centre
    cut = np.abs(y - layer) < 0.5 * dx  # one spacing thick
    zw = wz.max() + 0.5 * dx  # the wall's surface: half a spacing above its top layer
    for k, c in colour.items():
        s = cut & (m == k)
        ax.scatter(x[s] * 1e3, z[s] * 1e3, s=9, c=c, marker="s", linewidths=0)
    # reference cap: volume V = N dx^3 = pi r^3 (1 - c)^2 (2 + c) / 3
    V = np.count_nonzero(m == 0) * dx ** 3
    ct = math.cos(math.radians(theta))
    r = (3 * V / (math.pi * (1 - ct) ** 2 * (2 + ct))) ** (1 / 3)
    xc = np.mean(x[m == 0])
    a = np.linspace(-math.pi, math.pi, 400)
    cx, cz = xc + r * np.sin(a), zw - r * ct + r * np.cos(a)
    keep = cz >= zw
    ax.plot(cx[keep] * 1e3, cz[keep] * 1e3, "r-", lw=1)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
for ax in list(axes.flat)[len(items):]:
    ax.axis("off")
fig.tight_layout()
fig.savefig(out, dpi=110)
