#!/usr/bin/python3
"""Resample particle fields of a PoreSPH snapshot onto a regular grid (.vti) for volume rendering.

    scripts/resample_to_grid.py SNAPSHOT.vtu OUT.vti --spacing DX [--origin X Y Z]
        [--fields phase,material,damage] [--by current|reference]

Each particle is binned into the cell of the grid (spacing DX, origin given or the lowest particle
position minus DX/2) that contains its position: its current position (default: the deformed
sample, cracks that opened show as cells without solid) or, with --by reference, the solid's
reference_position (the undeformed image grid: one particle per voxel when DX is the image's voxel
size, so the result is the image with the run's damage painted on it). A cell keeps the value of
the last particle binned into it (particles are binned in order of increasing damage, so a cell
shared by a sound and a damaged particle shows the damage); empty cells get -1 for integer fields
and NaN for real ones. Vectors and tensors are written as their magnitude (Frobenius norm).

Open the .vti in ParaView with the Volume representation, colour by `damage` or `phase`.
Reading and writing use VTK's Python (Debian python3-vtk9) and numpy.
"""
import argparse
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("snapshot")
    p.add_argument("out")
    p.add_argument("--spacing", type=float, required=True, help="grid spacing (m), e.g. the voxel size")
    p.add_argument("--origin", type=float, nargs=3, default=None, help="corner of the grid (m)")
    p.add_argument("--fields", default="phase,material,damage")
    p.add_argument("--by", choices=["current", "reference"], default="current")
    a = p.parse_args()
    if not a.spacing > 0:
        sys.exit(f"resample_to_grid: --spacing must be positive, got {a.spacing}")

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(a.snapshot)
    reader.Update()
    grid = reader.GetOutput()
    if grid is None or grid.GetPoints() is None:
        sys.exit(f"resample_to_grid: {a.snapshot}: not a readable snapshot (.vtu)")
    pd = grid.GetPointData()
    x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    if a.by == "reference":
        ref = pd.GetArray("reference_position")
        if ref is None:
            sys.exit(f"resample_to_grid: {a.snapshot} has no reference_position (no solid): use --by current")
        xr = vtk_to_numpy(ref).astype(float)
        phase = vtk_to_numpy(pd.GetArray("phase")) if pd.GetArray("phase") else None
        if phase is not None:  # only solid particles have a reference position that means one
            keep = phase == 2
            x = np.where(keep[:, None], xr, x)
    n = x.shape[0]
    if n == 0:
        sys.exit(f"resample_to_grid: {a.snapshot} has no particles")
    dx = a.spacing
    origin = np.array(a.origin) if a.origin is not None else x.min(axis=0) - 0.5 * dx
    cell = np.floor((x - origin) / dx).astype(np.int64)
    if (cell < 0).any():
        sys.exit("resample_to_grid: particles below the grid origin; give a smaller --origin")
    dims = cell.max(axis=0) + 1
    flat = cell[:, 0] + dims[0] * (cell[:, 1] + dims[1] * cell[:, 2])
    damage = vtk_to_numpy(pd.GetArray("damage")) if pd.GetArray("damage") else None
    order = np.argsort(damage, kind="stable") if damage is not None else np.arange(n)

    image = vtk.vtkImageData()
    image.SetDimensions(int(dims[0]) + 1, int(dims[1]) + 1, int(dims[2]) + 1)  # cells = voxels
    image.SetOrigin(*origin)
    image.SetSpacing(dx, dx, dx)
    ncell = int(dims.prod())
    written = []
    for name in [f for f in a.fields.split(",") if f]:
        arr = pd.GetArray(name)
        if arr is None:
            print(f"resample_to_grid: {a.snapshot} has no field '{name}': skipped", file=sys.stderr)
            continue
        v = vtk_to_numpy(arr)
        if v.ndim > 1:
            v = np.linalg.norm(v.reshape(n, -1), axis=1)
        integer = np.issubdtype(v.dtype, np.integer)
        out = np.full(ncell, -1 if integer else np.nan, dtype=np.int32 if integer else np.float64)
        out[flat[order]] = v[order]  # later (more damaged) particles win
        va = numpy_to_vtk(out, deep=True)
        va.SetName(name)
        image.GetCellData().AddArray(va)
        written.append(name)
    occupied = np.zeros(ncell, dtype=np.int32)
    np.add.at(occupied, flat, 1)
    oa = numpy_to_vtk(occupied, deep=True)
    oa.SetName("particles_in_cell")
    image.GetCellData().AddArray(oa)

    w = vtk.vtkXMLImageDataWriter()
    w.SetFileName(a.out)
    w.SetInputData(image)
    if not w.Write():
        sys.exit(f"resample_to_grid: cannot write {a.out}")
    print(f"wrote {a.out}: {dims[0]} x {dims[1]} x {dims[2]} cells of {dx:g} m, fields "
          f"{', '.join(written) or 'none'}, {int((occupied > 0).sum())} occupied cells for {n} particles")


if __name__ == "__main__":
    main()
