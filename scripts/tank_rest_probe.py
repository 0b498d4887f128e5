#!/usr/bin/python3
"""Water at rest in a tank: how far it leaves rest and its left-right symmetry, per snapshot of a
run (docs/fluid.md "Water at rest on the lattice"; the scene samples/fluid_tank_at_rest.yaml or
any tank whose fluid starts mirror-symmetric about x = W/2).

    scripts/tank_rest_probe.py RUN_DIR [W]        (W: tank width, 0.3 m by default)

Columns: time; asym_x = rms over mirror pairs (x_i + x_j - W) (0 on a symmetric state: round-off
grows from ~1e-16 m); asym_vx the same for v_x; the mean displacement (dx, dy) of the water
block 0.1 < x < 0.2, 0.025 < y < 0.125 m at t = 0 (the floating test's box); rms and largest
speed of the water, its kinetic energy (J/m); mean vertical displacement of all water; highest
water particle. Ends with the growth rate of asym_x while it grows from 1e-11 to 1e-5 m.
Writes RUN_DIR/probe.txt. Needs python3-vtk9 (use /usr/bin/python3)."""
import glob
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def load(f):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(f)
    r.Update()
    g = r.GetOutput()
    x = vtk_to_numpy(g.GetPoints().GetData())[:, :2].copy()
    pd = g.GetPointData()
    d = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}
    return vtk_to_numpy(g.GetFieldData().GetArray("TimeValue"))[0], x, d


run = sys.argv[1]
W = float(sys.argv[2]) if len(sys.argv) > 2 else 0.3
files = sorted(glob.glob(run + "/snapshots/*.vtu"))
t0, x0, d0 = load(files[0])
ids = d0["id"]
fl = d0["phase"] == 0
fx, fid = x0[fl], ids[fl]
key = {(round(a / 1e-6), round(b / 1e-6)): i for i, (a, b) in zip(fid, fx)}
pairs = np.array([(i, key[(round((W - a) / 1e-6), round(b / 1e-6))]) for i, (a, b) in zip(fid, fx)
                  if (round((W - a) / 1e-6), round(b / 1e-6)) in key])
pairs = pairs[pairs[:, 0] < pairs[:, 1]]
block = fid[(fx[:, 0] > 0.1) & (fx[:, 0] < 0.2) & (fx[:, 1] > 0.025) & (fx[:, 1] < 0.125)]
n = ids.max() + 1
pos0 = np.zeros((n, 2))
pos0[ids] = x0
print("# t  asym_x(m)  asym_vx(m/s)  block_dx(m)  block_dy(m)  v_rms(m/s)  v_max  KE(J/m)  mean_dy  top_y")
rows = []
for f in files:
    t, x, d = load(f)
    P, V, M, ph = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n), np.full(n, -1)
    P[d["id"]], V[d["id"]], M[d["id"]], ph[d["id"]] = x, d["velocity"][:, :2], d["mass"], d["phase"]
    w = np.where(ph == 0)[0]
    ax = np.sqrt(np.mean((P[pairs[:, 0], 0] + P[pairs[:, 1], 0] - W) ** 2))
    av = np.sqrt(np.mean((V[pairs[:, 0], 0] + V[pairs[:, 1], 0]) ** 2))
    bd = (P[block] - pos0[block]).mean(axis=0) if len(block) else np.zeros(2)
    v2 = (V[w] ** 2).sum(axis=1)
    row = (t, ax, av, bd[0], bd[1], np.sqrt(v2.mean()), np.sqrt(v2.max()), 0.5 * (M[w] * v2).sum(),
           (P[w, 1] - pos0[w, 1]).mean(), P[w, 1].max())
    rows.append(row)
    print(" ".join("%.4e" % v for v in row))
rows = np.array(rows)
np.savetxt(run + "/probe.txt", rows)
m = (rows[:, 1] > 1e-11) & (rows[:, 1] < 1e-5)
if m.sum() >= 3:
    k = np.polyfit(rows[m, 0], np.log(rows[m, 1]), 1)[0]
    print("# growth rate of asym_x: %.1f /s over t = %.2f..%.2f s" % (k, rows[m, 0].min(), rows[m, 0].max()))
late = rows[rows[:, 0] >= rows[-1, 0] - 0.5]
print("# last 0.5 s: asym_x max %.3e m, v_rms mean %.3e m/s, block |dx| max %.3e m, block dy %.3e m"
      % (late[:, 1].max(), late[:, 5].mean(), np.abs(late[:, 3]).max(), late[-1, 4]))
