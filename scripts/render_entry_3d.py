#!/usr/bin/python3
"""Renders dumps of the 3D capillary-entry test (tests/validation/fluid_capillary_entry_3d_case.hpp,
written to the build folder as fluid_capillary_entry_3d_*.txt) (x y z code per line; code 1 water, -1 gas,
0.5 wall). Usage: render_entry_3d.py OUT.png "title=dump.txt" ... Per dump, the mid-plane slab through the tube axis (x-y) and the tube's cross-section
(y-z) 0.5 w past the entrance."""
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

out = sys.argv[1]
xs, w = 1.6, 0.6  # mm: tube entrance, side
pairs = [a.split("=", 1) for a in sys.argv[2:]]  # title=path
n = len(pairs)
fig, axes = plt.subplots(2, n, figsize=(4.3 * n, 5.2), gridspec_kw={"height_ratios": [1, 1.25]})
axes = np.array(axes).reshape(2, n)
for k, (title, path) in enumerate(pairs):
    d = np.loadtxt(path)
    x, y, z, c = d[:, 0] * 1e3, d[:, 1] * 1e3, d[:, 2] * 1e3, d[:, 3]
    cols = ((0.5, "0.6"), (1, "tab:blue"), (-1, "tab:orange"))
    s = np.abs(z - 0.5) < 0.1  # the two lattice layers either side of the axis
    ax = axes[0, k]
    for code, col in cols:
        m = s & (c == code)
        ax.scatter(x[m], y[m], s=7, c=col, linewidths=0)
    ax.axvline(xs, color="k", lw=0.5, ls=":")
    ax.set_aspect("equal"); ax.set_title(title, fontsize=9); ax.set_xlabel("x [mm]"); ax.set_ylabel("y [mm]")
    s2 = np.abs(x - (xs + 0.5 * w)) < 0.05
    ax = axes[1, k]
    for code, col in cols:
        m = s2 & (c == code)
        ax.scatter(y[m], z[m], s=60, c=col, linewidths=0)
    ax.set_aspect("equal"); ax.set_xlabel("y [mm]"); ax.set_ylabel("z [mm]")
    ax.set_title("section 0.5 w past the entrance", fontsize=8)
fig.tight_layout()
fig.savefig(out, dpi=100)
print("wrote", out)
