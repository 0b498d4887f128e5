#!/usr/bin/python3
"""Contact angle of a 2D drop on a circular wall from a run's snapshots (the reading of
tests/validation/fluid_wetting_curved_case.hpp, for samples/fluid_drop_on_cylinder_120.yaml):
midpoints of liquid-gas pairs closer than 1.5 dx more than 2 dx from the wall circle, the Kasa
circle through them, cut with the wall circle; the angle (through the liquid) against the local
wall tangent at the contact point. Prints each snapshot's angle and the mean over the window.

Usage: wetting_angle_from_snapshots.py RUN_DIR --centre X Y --radius RC --dx DX
         [--liquid ID] [--gas ID] [--from T] [--to T] [--inside]
(material ids as in the scene file's order; times in s, read from results.pvd)."""
import argparse
import pathlib
import re
import sys

import numpy as np
import vtk
from scipy.spatial import cKDTree
from vtk.util.numpy_support import vtk_to_numpy

p = argparse.ArgumentParser()
p.add_argument("run")
p.add_argument("--centre", type=float, nargs=2, required=True)
p.add_argument("--radius", type=float, required=True)
p.add_argument("--dx", type=float, required=True)
p.add_argument("--liquid", type=int, default=0)
p.add_argument("--gas", type=int, default=1)
p.add_argument("--from", dest="t0", type=float, default=0.06)
p.add_argument("--to", dest="t1", type=float, default=0.12)
p.add_argument("--inside", action="store_true", help="drop inside a cavity (default: on a cylinder)")
a = p.parse_args()

run = pathlib.Path(a.run)
pvd = run / "results.pvd"
if not pvd.exists():
    sys.exit(f"{pvd}: not found (run directory of `poresph run`)")
steps = [(float(t), f) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', pvd.read_text())]
C, Rc, dx = np.array(a.centre), a.radius, a.dx
angles = []
for t, f in steps:
    if t < a.t0 - 1e-9 or t > a.t1 + 1e-9:
        continue
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(run / f))
    r.Update()
    g = r.GetOutput()
    x = vtk_to_numpy(g.GetPoints().GetData())[:, :2]
    arr = g.GetPointData().GetArray("material")
    if arr is None:
        sys.exit(f"{f}: no field 'material'")
    m = vtk_to_numpy(arr).astype(int)
    L, G = x[m == a.liquid], x[m == a.gas]
    pairs = cKDTree(L).query_ball_tree(cKDTree(G), 1.5 * dx)
    mids = np.array([0.5 * (L[i] + G[j]) for i, js in enumerate(pairs) for j in js])
    mids = mids[np.abs(np.linalg.norm(mids - C, axis=1) - Rc) > 2 * dx]
    A = np.c_[mids, np.ones(len(mids))]
    s = np.linalg.lstsq(A, -(mids ** 2).sum(1), rcond=None)[0]
    Cd = -0.5 * s[:2]
    rd = np.sqrt(Cd @ Cd - s[2])
    e = Cd - C
    d = np.linalg.norm(e)
    along = (Rc * Rc - rd * rd + d * d) / (2 * d)
    across = np.sqrt(max(0.0, Rc * Rc - along * along))
    u = e / d
    P = C + along * u + across * np.array([-u[1], u[0]])
    nd = (P - Cd) / rd
    nw = (C - P) / Rc if a.inside else (P - C) / Rc
    ang = np.degrees(np.arccos(np.clip(nd @ nw, -1, 1)))
    angles.append(ang)
    print(f"t {t:.4f} s: {ang:.2f} deg (drop radius {rd / dx:.2f} dx, {len(mids)} points)")
if not angles:
    sys.exit("no snapshot in the window")
print(f"mean {np.mean(angles):.2f} deg over {len(angles)} snapshots ({min(angles):.2f} to {max(angles):.2f})")
