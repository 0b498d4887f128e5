#!/usr/bin/python3
"""Where along the flow axis things happen: per-layer counts of damaged solid and of each fluid.

    scripts/profile_along_axis.py RUN_DIR [--axis z] [--lo 0.0006 --hi 0.0022] [--layer DX]
        [--threshold 0.5] [--every 1] [--csv OUT.csv]

For each snapshot of RUN_DIR/snapshots (every --every-th), the sample [lo, hi) along --axis is cut
into layers of thickness --layer (default: the run's particle spacing, read from RUN_DIR/run.yaml),
and per layer it prints
  - the number of solid particles with damage > --threshold, binned by their REFERENCE position
    (where the material was, not where it moved), and
  - the number of fluid particles of each material index (scene order) in the layer, by their
    current positions.
Used in docs/drainage.md to show that the main job's damage follows the gas front. Without --lo/--hi
the range of the solid's reference positions is used. Needs python3-vtk9 and numpy (Debian).
"""
import argparse
import csv
import glob
import os
import re
import sys

import numpy as np


def read(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy as v
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pd = g.GetPointData()
    if g.GetNumberOfPoints() == 0:
        raise SystemExit(f"profile_along_axis: {path}: no particles")
    out = {"x": v(g.GetPoints().GetData())}
    for name in ("damage", "reference_position", "material", "phase"):
        a = pd.GetArray(name)
        if a is not None:
            out[name] = v(a)
    return out


def spacing_of(run):
    """The top-level `spacing:` of the parameters the run used (RUN_DIR/run.yaml)."""
    path = os.path.join(run, "run.yaml")
    try:
        with open(path) as f:
            for line in f:
                m = re.match(r"spacing:\s*([-+0-9.eE]+)\s*(#.*)?$", line)
                if m:
                    return float(m.group(1))
    except OSError as e:
        raise SystemExit(f"profile_along_axis: {path}: {e.strerror}; give --layer")
    raise SystemExit(f"profile_along_axis: {path}: no top-level 'spacing:'; give --layer")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", help="output folder of `poresph run` (with snapshots/)")
    p.add_argument("--axis", default="z", choices=["x", "y", "z"])
    p.add_argument("--lo", type=float, default=None)
    p.add_argument("--hi", type=float, default=None)
    p.add_argument("--layer", type=float, default=None,
                   help="layer thickness in metres (default: the run's particle spacing, from RUN_DIR/run.yaml)")
    p.add_argument("--threshold", type=float, default=0.5, help="damage above which a particle counts")
    p.add_argument("--every", type=int, default=1, help="use every N-th snapshot")
    p.add_argument("--csv", default=None, help="also write the table as CSV")
    a = p.parse_args(argv)
    snaps = sorted(glob.glob(os.path.join(a.run, "snapshots", "step_*.vtu")))
    if not snaps:
        raise SystemExit(f"profile_along_axis: {a.run}: no snapshots/step_*.vtu")
    if a.layer is None:
        a.layer = spacing_of(a.run)
    if a.layer <= 0 or a.every < 1:
        raise SystemExit(f"profile_along_axis: --layer {a.layer} and --every {a.every} must be positive")
    k = "xyz".index(a.axis)
    rows = []
    for path in snaps[:: a.every]:
        s = read(path)
        if "damage" not in s or "reference_position" not in s:
            print(f"{os.path.basename(path)}: no damage field (no damageable solid): damage counts skipped")
        # phases (libcore/phases.hpp): 0 fluid, 1 wall, 2 solid, 3 rigid
        phase = s["phase"] if "phase" in s else np.zeros(len(s["x"]), int)
        solid = phase == 2
        lo, hi = a.lo, a.hi
        if lo is None or hi is None:
            if "reference_position" not in s or not solid.any():
                raise SystemExit("profile_along_axis: give --lo and --hi (no solid to take the range from)")
            ref = s["reference_position"][solid, k]
            lo = ref.min() - 0.5 * a.layer if lo is None else lo
            hi = ref.max() + 0.5 * a.layer if hi is None else hi
        n = max(1, int(round((hi - lo) / a.layer)))
        line = {"snapshot": os.path.basename(path)}
        if "damage" in s and "reference_position" in s:
            d = s["damage"] > a.threshold
            z = s["reference_position"][d, k]
            z = z[(z >= lo) & (z < hi)]
            line["damaged"] = np.bincount(((z - lo) / a.layer).astype(int), minlength=n)[:n]
        if "material" in s:
            z = s["x"][:, k]
            inside = (z >= lo) & (z < hi) & (phase == 0)
            for m in np.unique(s["material"][inside]):
                zz = z[inside & (s["material"] == m)]
                line[f"material{m}"] = np.bincount(((zz - lo) / a.layer).astype(int), minlength=n)[:n]
        rows.append(line)
        print(f"{line['snapshot']}  layers {n} from {a.axis} = {lo:.6g} (layer 0) to {hi:.6g}")
        for key, val in line.items():
            if key != "snapshot":
                print(f"  {key:>10}: " + " ".join(f"{c:3d}" for c in val))
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["snapshot", "quantity", "layer", "count"])
            for line in rows:
                for key, val in line.items():
                    if key != "snapshot":
                        for i, c in enumerate(val):
                            w.writerow([line["snapshot"], key, i, int(c)])
    return 0


if __name__ == "__main__":
    sys.exit(main())
