#!/usr/bin/python3
"""Renders the damage field of the plate with an inclusion (CSV dumps of
tests/validation/damage_plate_case.hpp, PORESPH_PLATE_DUMP: columns X,Y,x,y,D) on the reference
lattice, side by side.

Usage: render_plate_damage.py OUT.png DUMP1.csv TITLE1 [DUMP2.csv TITLE2 ...]"""
import sys, numpy as np, matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
out = sys.argv[1]; items = sys.argv[2:]
n = len(items)//2
fig, axs = plt.subplots(1, n, figsize=(3.3*n+0.8, 3.5), constrained_layout=True)
axs = np.atleast_1d(axs)
L = 0.3
for k in range(n):
    d = np.genfromtxt(items[2*k], delimiter=",", names=True)
    X, Y = d["X"], d["Y"]
    dx = np.min(np.diff(np.unique(np.round(X, 9))))
    m = int(round(L/dx))
    ix = np.clip(np.floor((X + L/2)/dx).astype(int), 0, m-1); iy = np.clip(np.floor((Y + L/2)/dx).astype(int), 0, m-1)
    g = np.full((m, m), np.nan); g[iy, ix] = d["D"]
    ax = axs[k]
    im = ax.imshow(g, origin="lower", extent=[-150, 150, -150, 150], vmin=0, vmax=1, cmap="viridis", interpolation="nearest")
    ax.set_title(items[2*k+1], fontsize=8); ax.set_xlabel("X [mm]")
fig.colorbar(im, ax=axs.tolist(), shrink=0.8, label="D")
fig.savefig(out, dpi=110)
