#!/usr/bin/python3
"""Renders a PoreSPH snapshot (.vtu) to a PNG: particles coloured by one field (2D, or a slab of a
3D run). Needs Debian's python3-vtk9 and python3-matplotlib (use /usr/bin/python3).

Usage: render_particles.py SNAPSHOT.vtu OUT.png [--field NAME] [--component K]
                           [--slab-axis z --slab-center C --slab-width W]"""
import argparse

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

p = argparse.ArgumentParser()
p.add_argument("snapshot")
p.add_argument("out")
p.add_argument("--field", default="pressure")
p.add_argument("--component", type=int, default=-1, help="-1: magnitude of a vector field")
p.add_argument("--slab-axis", choices="xyz", default="z")
p.add_argument("--slab-center", type=float, default=None)
p.add_argument("--slab-width", type=float, default=None)
a = p.parse_args()

r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(a.snapshot)
r.Update()
grid = r.GetOutput()
x = vtk_to_numpy(grid.GetPoints().GetData())
arr = grid.GetPointData().GetArray(a.field)
if arr is None:
    names = [grid.GetPointData().GetArrayName(i) for i in range(grid.GetPointData().GetNumberOfArrays())]
    raise SystemExit(f"no field '{a.field}' in {a.snapshot}; fields: {', '.join(names)}")
v = vtk_to_numpy(arr)
if v.ndim > 1:
    v = np.linalg.norm(v, axis=1) if a.component < 0 else v[:, a.component]
axis = "xyz".index(a.slab_axis)
keep = np.ones(len(x), bool)
if a.slab_center is not None and a.slab_width is not None:
    keep = np.abs(x[:, axis] - a.slab_center) <= 0.5 * a.slab_width
plane = [k for k in range(3) if k != axis][:2] if np.ptp(x[:, 2]) > 0 else [0, 1]
fig, ax = plt.subplots(figsize=(7, 6))
sc = ax.scatter(x[keep, plane[0]], x[keep, plane[1]], c=v[keep], s=8, cmap="viridis")
fig.colorbar(sc, ax=ax, label=a.field)
ax.set_aspect("equal")
ax.set_xlabel("xyz"[plane[0]] + " [m]")
ax.set_ylabel("xyz"[plane[1]] + " [m]")
ax.set_title(a.snapshot.split("/")[-1])
fig.tight_layout()
fig.savefig(a.out, dpi=110)
print(f"wrote {a.out}")
