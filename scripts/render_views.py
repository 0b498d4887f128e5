#!/usr/bin/python3
"""Standard views of a PoreSPH run as PNG files: the phases in 3D, and xy and yz cuts of fields.

    scripts/render_views.py RUN_DIR_OR_SNAPSHOT [--out DIR] [--fields damage,max_principal_stress]
        [--step last|first|N] [--cut-width W]

RUN_DIR: an output folder of `poresph run` (its results.pvd gives the snapshots; the last one by
default); or one snapshot .vtu. Writes to --out (default RUN_DIR/views):
  phases_3d.png        every particle at its position, coloured by phase (3D runs: a perspective
                       scatter; 2D runs: the plane)
  <field>_xy.png       the particles within half a spacing (or --cut-width) of the mid-plane
  <field>_yz.png       normal to z (xy) and to x (yz), coloured by the field (2D runs: xy only)
Fields: any point array of the snapshot (vectors and tensors: their magnitude / Frobenius norm, or
name:K for component K). A requested field the snapshot lacks is skipped with a note, so the
default set (phase, pressure, damage, max_principal_stress) works for every run;
max_principal_stress is computed from the stress tensor when the snapshot has no such array. Reading uses
VTK's Python (Debian python3-vtk9), drawing matplotlib (python3-matplotlib).
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

SOLID_FIELDS = ("damage", "max_principal_stress", "stress", "strain", "displacement")
PHASE_NAMES = {0: "fluid", 1: "wall", 2: "solid", 3: "rigid"}  # libcore/phases.hpp


def snapshot_of(path, step):
    if path.endswith(".vtu"):
        return path
    pvd = os.path.join(path, "results.pvd")
    if not os.path.exists(pvd):
        raise SystemExit(f"render_views: {path}: no results.pvd (give a run folder or a .vtu)")
    files = [(float(d.get("timestep")), d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]
    if not files:
        raise SystemExit(f"render_views: {pvd}: no snapshot listed")
    if step == "last":
        t, f = files[-1]
    elif step == "first":
        t, f = files[0]
    else:
        k = int(step)
        if not -len(files) <= k < len(files):
            raise SystemExit(f"render_views: --step {step}: {len(files)} snapshots")
        t, f = files[k]
    return os.path.join(path, f)


def read(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if g is None or g.GetNumberOfPoints() == 0:
        raise SystemExit(f"render_views: {path}: no particles (not a PoreSPH snapshot?)")
    x = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    pd = g.GetPointData()
    fields = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}
    return x, fields


def values(fields, spec):
    name, _, comp = spec.partition(":")
    if name not in fields:
        return None
    v = np.asarray(fields[name], dtype=float)
    if v.ndim > 1:
        v = v[:, int(comp)] if comp else np.linalg.norm(v, axis=1)
    return v


def spacing(fields, dim):
    # The particle spacing from the particle volumes m / rho (dx^D on the initial lattice).
    if "mass" in fields and "density" in fields:
        vol = np.asarray(fields["mass"], float) / np.maximum(np.asarray(fields["density"], float), 1e-300)
        return float(np.median(vol)) ** (1.0 / dim)
    return None


def principal_max(fields, dim):
    """Largest eigenvalue of the (symmetric) stress tensor per particle, when 'stress' exists."""
    if "stress" not in fields:
        return None
    s = np.asarray(fields["stress"], float)
    n = int(round(np.sqrt(s.shape[1]))) if s.ndim == 2 else 0
    if n < 1 or n * n != s.shape[1]:
        return None
    t = s.reshape(-1, n, n)
    return np.linalg.eigvalsh(0.5 * (t + np.transpose(t, (0, 2, 1))))[:, -1]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run")
    p.add_argument("--out", default=None)
    p.add_argument("--fields", default="phase,pressure,damage,max_principal_stress")
    p.add_argument("--step", default="last")
    p.add_argument("--cut-width", type=float, default=None)
    a = p.parse_args(argv)
    snap = snapshot_of(a.run, a.step)
    out = a.out or os.path.join(a.run if os.path.isdir(a.run) else os.path.dirname(snap), "views")
    os.makedirs(out, exist_ok=True)
    x, fields = read(snap)
    dim = 3 if np.ptp(x[:, 2]) > 0 else 2
    dx = spacing(fields, dim)
    if "max_principal_stress" not in fields:
        mp = principal_max(fields, dim)
        if mp is not None:
            fields["max_principal_stress"] = mp  # from the stress tensor
    written = []

    # ---- phases ----
    phase = values(fields, "phase")
    if phase is None:
        phase = np.zeros(len(x))
    fig = plt.figure(figsize=(7, 6))
    if dim == 3:
        ax = fig.add_subplot(projection="3d")
        for ph in np.unique(phase):
            m = phase == ph
            ax.scatter(x[m, 0], x[m, 1], x[m, 2], s=2, alpha=0.5 if ph == 0 else 0.15,
                       label=PHASE_NAMES.get(int(ph), str(int(ph))))
        ax.set_zlabel("z [m]")
    else:
        ax = fig.add_subplot()
        for ph in np.unique(phase):
            m = phase == ph
            ax.scatter(x[m, 0], x[m, 1], s=6, label=PHASE_NAMES.get(int(ph), str(int(ph))))
        ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(markerscale=4)
    ax.set_title(os.path.basename(snap) + ": phases")
    fig.tight_layout()
    path = os.path.join(out, "phases_3d.png" if dim == 3 else "phases.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    written.append(path)

    # ---- cuts ----
    if a.cut_width:
        width = a.cut_width
    elif dx:
        width = 1.01 * dx
    else:
        raise SystemExit("render_views: no mass/density fields to tell the spacing: give --cut-width")
    cuts = [("xy", 2, (0, 1)), ("yz", 0, (1, 2))] if dim == 3 else [("xy", None, (0, 1))]
    for spec in [f for f in a.fields.split(",") if f]:
        v = values(fields, spec)
        if v is None:
            print(f"render_views: {os.path.basename(snap)} has no field '{spec}': skipped "
                  f"(fields: {', '.join(sorted(fields))})")
            continue
        for name, normal, (i, j) in cuts:
            keep = np.ones(len(x), bool)
            if normal is not None:
                mid = 0.5 * (x[:, normal].min() + x[:, normal].max())
                centre = x[np.argmin(np.abs(x[:, normal] - mid)), normal]
                keep = np.abs(x[:, normal] - centre) <= 0.5 * width
            fig, ax = plt.subplots(figsize=(7, 6))
            size = max(2.0, 4e4 / max(1, keep.sum()))
            # Solid fields (stress, damage) on solid particles only; the others in light grey.
            show = keep.copy()
            if spec.split(":")[0] in SOLID_FIELDS and "phase" in fields:
                solid = np.isin(np.asarray(fields["phase"]), (2, 3))
                ax.scatter(x[keep & ~solid, i], x[keep & ~solid, j], c="0.85", s=size, marker="s")
                show = keep & solid
            sc = ax.scatter(x[show, i], x[show, j], c=v[show], s=size, cmap="viridis", marker="s")
            fig.colorbar(sc, ax=ax, label=spec)
            ax.set_aspect("equal")
            ax.set_xlabel("xyz"[i] + " [m]")
            ax.set_ylabel("xyz"[j] + " [m]")
            ax.set_title(f"{os.path.basename(snap)}: {spec}, {name} cut")
            fig.tight_layout()
            path = os.path.join(out, f"{spec.replace(':', '_')}_{name}.png")
            fig.savefig(path, dpi=110)
            plt.close(fig)
            written.append(path)
    for w in written:
        print("render_views: wrote", w)
    return 0


if __name__ == "__main__":
    sys.exit(main())
