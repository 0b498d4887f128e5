#!/usr/bin/python3
"""Gas history of a 2D two-phase PoreSPH run (trapped bubble, Haines jump; docs/fluid.md).

For each snapshot of RUN/results.pvd prints: time, number of gas particles, gas mass, gas mass
centre (x, y), the fraction of the gas mass inside a box (--box x0 x1 y0 y1, e.g. a dead-end
pore), the gas front (largest x of a gas particle, optionally only those with y in --band y0 y1
and x below --front-max), the largest fluid speed, and the mass-weighted mean pressure of the gas
and of the water. Gas = material --gas (index in the scene's material list, default 1), water =
--water (default 0). Needs Debian's python3-vtk9 (use /usr/bin/python3).

Usage: gas_history.py RUN [--box x0 x1 y0 y1] [--band y0 y1] [--front-max X] [--beyond X]"""
import argparse
import os
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

p = argparse.ArgumentParser()
p.add_argument("run")
p.add_argument("--gas", type=int, default=1)
p.add_argument("--water", type=int, default=0)
p.add_argument("--box", type=float, nargs=4, default=None)
p.add_argument("--band", type=float, nargs=2, default=None)
p.add_argument("--front-max", type=float, default=None)
p.add_argument("--beyond", type=float, default=None, help="also print the gas area (mm^2, 2D) with x in (X, front-max)")
a = p.parse_args()

print("t_ms n_gas gas_mass_rel xc_mm yc_mm in_box front_mm vmax_m_s p_gas_Pa p_water_Pa" + (" area_beyond_mm2" if a.beyond is not None else ""))
m0 = None
for ds in ET.parse(os.path.join(a.run, "results.pvd")).getroot().iter("DataSet"):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(os.path.join(a.run, ds.get("file")))
    r.Update()
    g = r.GetOutput()
    pd = g.GetPointData()
    x = vtk_to_numpy(g.GetPoints().GetData())
    mat = vtk_to_numpy(pd.GetArray("material")).astype(int)
    m = vtk_to_numpy(pd.GetArray("mass"))
    v = np.linalg.norm(vtk_to_numpy(pd.GetArray("velocity")), axis=1)
    pr = vtk_to_numpy(pd.GetArray("pressure"))
    gas, water = mat == a.gas, mat == a.water
    mg = m[gas].sum()
    m0 = mg if m0 is None else m0
    xc = (m[gas] * x[gas, 0]).sum() / mg
    yc = (m[gas] * x[gas, 1]).sum() / mg
    inbox = float("nan")
    if a.box:
        b = a.box
        ib = gas & (x[:, 0] >= b[0]) & (x[:, 0] <= b[1]) & (x[:, 1] >= b[2]) & (x[:, 1] <= b[3])
        inbox = m[ib].sum() / mg
    sel = gas.copy()
    if a.band:
        sel &= (x[:, 1] >= a.band[0]) & (x[:, 1] <= a.band[1])
    if a.front_max is not None:
        sel &= x[:, 0] <= a.front_max
    front = x[sel, 0].max() if sel.any() else float("nan")
    fluid = gas | water
    if a.beyond is not None:
        nb = gas & (x[:, 0] > a.beyond) & (x[:, 0] <= (a.front_max if a.front_max is not None else np.inf))
        rho = vtk_to_numpy(pd.GetArray("density"))
        beyond = 1e6 * (m[nb] / rho[nb]).sum()
    pg = (m[gas] * pr[gas]).sum() / mg
    pw = (m[water] * pr[water]).sum() / m[water].sum()
    print(f"{1e3 * float(ds.get('timestep')):.2f} {gas.sum()} {mg / m0:.6f} {1e3 * xc:.4f} "
          f"{1e3 * yc:.4f} {inbox:.4f} {1e3 * front:.4f} {v[fluid].max():.4f} {pg:.2f} {pw:.2f}"
          + (f" {beyond:.4f}" if a.beyond is not None else ""))
