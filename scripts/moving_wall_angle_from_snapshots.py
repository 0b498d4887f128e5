#!/usr/bin/python3
"""Contact angle of a 2D drop on a flat wall from a run's snapshots, for a drop that travels
along a periodic x axis (samples/fluid_drop_on_moving_wall.yaml; the reading of
tests/validation/fluid_wetting_moving_case.hpp): liquid and gas unwrapped about the drop's
centroid, midpoints of liquid-gas pairs closer than 1.5 dx more than 2 dx above the wall surface
y = Y0, the Kasa circle through them cut with the wall (cos theta = -(y_c - Y0) / r), and per side
(downstream "front", upstream "rear" of the circle's centre) a geometric circle fit of that half
alone. Also the drop's speed: the mean x velocity of the liquid over --velocity (the plate's).
Prints each snapshot's readings and the means over the window.

Usage: moving_wall_angle_from_snapshots.py RUN_DIR --dx DX --period LX [--wall Y0]
         [--velocity U] [--liquid ID] [--gas ID] [--from T] [--to T] [--png OUT]
(--png: the drops of the first and last snapshots of the window and of t = 0, unwrapped, with
the circles fitted to them, side by side.)
(material ids as in the scene file's order; times in s, read from results.pvd)."""
import argparse
import pathlib
import re
import sys

import numpy as np
import vtk
from scipy.optimize import least_squares
from scipy.spatial import cKDTree
from vtk.util.numpy_support import vtk_to_numpy

p = argparse.ArgumentParser()
p.add_argument("run")
p.add_argument("--dx", type=float, required=True)
p.add_argument("--period", type=float, required=True, help="length of the periodic x axis")
p.add_argument("--wall", type=float, default=0.0, help="height of the wall's surface")
p.add_argument("--velocity", type=float, default=1.0, help="plate velocity (the speed is printed over it)")
p.add_argument("--liquid", type=int, default=0)
p.add_argument("--gas", type=int, default=1)
p.add_argument("--from", dest="t0", type=float, default=0.06)
p.add_argument("--to", dest="t1", type=float, default=0.12)
p.add_argument("--png", help="picture of the drop at t = 0 and at the window's ends")
a = p.parse_args()

run = pathlib.Path(a.run)
pvd = run / "results.pvd"
if not pvd.exists():
    sys.exit(f"{pvd}: not found (run directory of `poresph run`)")
steps = [(float(t), f) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', pvd.read_text())]
dx, Lx = a.dx, a.period


def kasa(P):
    s = np.linalg.lstsq(np.c_[P, np.ones(len(P))], -(P ** 2).sum(1), rcond=None)[0]
    c = -0.5 * s[:2]
    return c, np.sqrt(c @ c - s[2])


def geometric(P):
    c, r = kasa(P)
    q = least_squares(lambda q: np.hypot(P[:, 0] - q[0], P[:, 1] - q[1]) - q[2], [c[0], c[1], r]).x
    return q[:2], q[2]


def angle(c, r):
    return np.degrees(np.arccos(np.clip(-(c[1] - a.wall) / r, -1, 1)))


rows, shots = [], []
for t, f in steps:
    if (t < a.t0 - 1e-9 or t > a.t1 + 1e-9) and t > 1e-12:
        continue
    rd = vtk.vtkXMLUnstructuredGridReader()
    rd.SetFileName(str(run / f))
    rd.Update()
    g = rd.GetOutput()
    x = vtk_to_numpy(g.GetPoints().GetData())[:, :2].copy()
    for name in ("material", "velocity"):
        if g.GetPointData().GetArray(name) is None:
            sys.exit(f"{f}: no field '{name}'")
    m = vtk_to_numpy(g.GetPointData().GetArray("material")).astype(int)
    v = vtk_to_numpy(g.GetPointData().GetArray("velocity"))
    L = x[m == a.liquid]
    xc = (np.angle(np.exp(2j * np.pi * L[:, 0] / Lx).mean()) / (2 * np.pi) * Lx) % Lx  # circular mean
    x[:, 0] -= Lx * np.round((x[:, 0] - xc) / Lx)  # unwrap about the drop
    L, G = x[m == a.liquid], x[m == a.gas]
    pairs = cKDTree(L).query_ball_tree(cKDTree(G), 1.5 * dx)
    mids = np.array([0.5 * (L[i] + G[j]) for i, js in enumerate(pairs) for j in js])
    mids = mids[mids[:, 1] > a.wall + 2 * dx]
    c, r = kasa(mids)
    front, rear = mids[mids[:, 0] > c[0]], mids[mids[:, 0] <= c[0]]
    full, fa, ra = angle(c, r), angle(*geometric(front)), angle(*geometric(rear))
    speed = v[m == a.liquid, 0].mean() / a.velocity
    shots.append((t, x.copy(), m.copy(), c, r, full, speed))
    if t < a.t0 - 1e-9:
        continue
    rows.append((full, fa, ra, speed))
    print(f"t {t:.4f} s: {full:.2f} deg (front {fa:.2f}, rear {ra:.2f}; drop radius {r / dx:.2f} dx, "
          f"{len(mids)} points), drop at x = {L[:, 0].mean():.5f} m, speed {speed:.4f} U")
if not rows:
    sys.exit("no snapshot in the window")
R = np.array(rows)
print(f"mean {R[:, 0].mean():.2f} deg over {len(R)} snapshots ({R[:, 0].min():.2f} to {R[:, 0].max():.2f}); "
      f"front {R[:, 1].mean():.2f}, rear {R[:, 2].mean():.2f}; drop speed {R[:, 3].mean():.4f} U")

if a.png:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pick = [shots[0], next(s for s in shots if s[0] >= a.t0 - 1e-9), shots[-1]]
    fig, axs = plt.subplots(1, 3, figsize=(13, 3.2))
    for ax, (t, x, m, c, r, full, speed) in zip(axs, pick):
        xc = x[m == a.liquid, 0].mean()
        for mid, col in ((a.gas, "#d0e4f5"), (a.liquid, "#1f3b73")):
            ax.scatter((x[m == mid, 0] - xc) / dx, (x[m == mid, 1] - a.wall) / dx, s=6, c=col, lw=0)
        other = (m != a.liquid) & (m != a.gas)
        ax.scatter((x[other, 0] - xc) / dx, (x[other, 1] - a.wall) / dx, s=6, c="0.6", lw=0)
        if t > 1e-12:
            q = np.linspace(0, 2 * np.pi, 400)
            ax.plot((c[0] - xc + r * np.cos(q)) / dx, (c[1] - a.wall + r * np.sin(q)) / dx, "r-", lw=1)
            ax.set_title(f"t = {1e3 * t:.0f} ms: {full:.1f} deg, drop {speed:.2f} U")
        else:
            ax.set_title("t = 0 (rectangle, at rest)")
        ax.set_xlim(-0.5 * Lx / dx, 0.5 * Lx / dx)
        ax.set_ylim(-3, None)
        ax.set_aspect("equal")
        ax.set_xlabel("x - x_drop [dx]")
    axs[0].set_ylabel("y [dx]")
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)
    print(f"wrote {a.png}")
