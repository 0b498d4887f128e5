#!/usr/bin/python3
"""Plot chosen columns of one or more PoreSPH timeseries.csv files against time.

    scripts/plot_timeseries.py RUN/timeseries.csv [MORE.csv ...] --columns a,b,c --out plot.png
        [--labels name1,name2,...] [--x time]

One panel per column, one line per file (a sweep passes every case). Columns that a file lacks
are skipped for that file; a column no file has is an error naming the columns there are.
Default columns: the drainage columns (porosity, gas saturation, damaged fraction) where present,
else kinetic_energy. A column named *_time (percolation time, flow-path time) holds -1 until the
event happens: those rows are left out of its panel instead of drawn as a jump from -1 s.
Needs matplotlib (Debian: python3-matplotlib; scripts/install-deps.sh).
"""
import argparse
import csv
import math
import sys

DEFAULT = ["drainage_porosity", "drainage_gas_saturation", "drainage_damaged_fraction"]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise SystemExit(f"plot_timeseries: {path}: empty file")
    header, data = rows[0], rows[1:]
    cols = {name: [] for name in header}
    for r in data:
        for name, v in zip(header, r):
            try:
                cols[name].append(float(v))
            except ValueError:
                cols[name].append(math.nan)
    return header, cols


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("files", nargs="+", help="timeseries.csv files")
    p.add_argument("--columns", default="", help="comma-separated column names")
    p.add_argument("--out", required=True, help="output PNG")
    p.add_argument("--labels", default="", help="comma-separated legend labels, one per file")
    p.add_argument("--x", default="time", help="column on the horizontal axis (default time)")
    a = p.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = [read(f) for f in a.files]
    labels = a.labels.split(",") if a.labels else [f for f in a.files]
    if len(labels) != len(runs):
        raise SystemExit(f"plot_timeseries: {len(labels)} labels for {len(runs)} files")
    every = sorted({c for h, _ in runs for c in h})
    if a.columns:
        columns = [c for c in a.columns.split(",") if c]
    else:
        columns = [c for c in DEFAULT if c in every] or ["kinetic_energy"]
    unknown = [c for c in columns + [a.x] if c not in every]
    if unknown:
        raise SystemExit("plot_timeseries: no file has the column(s) " + ", ".join(unknown) +
                         "; columns: " + ", ".join(every))
    fig, axes = plt.subplots(len(columns), 1, figsize=(7, 2.6 * len(columns)), sharex=True, squeeze=False)
    for ax, col in zip(axes[:, 0], columns):
        for (header, cols), label in zip(runs, labels):
            if col in cols and a.x in cols:
                ys = cols[col]
                if col.endswith("_time"):  # -1 = "not yet" (docs/drainage.md), not a time
                    ys = [y if y >= 0 else math.nan for y in ys]
                ax.plot(cols[a.x], ys, marker="." if len(cols[col]) < 30 else None, label=label)
        ax.set_ylabel(col.replace("_", " "))
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel(a.x + (" (s)" if a.x == "time" else ""))
    if len(runs) > 1:
        axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(f"plot_timeseries: {a.out} ({len(columns)} columns, {len(runs)} runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
