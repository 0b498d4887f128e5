#!/usr/bin/python3
"""Error against wall time of a `poresph study` (docs/choosing-settings.md).

    scripts/plot_study.py DIR/study.csv --out DIR/study.png [--title TEXT] [--label COLUMNS]

Log-log (x: wall time, or CPU time with --cost cpu): one marker per healthy run (error > 0), the Pareto front (no other healthy run both
faster and more accurate) joined by a line, the reference run (the finest, error 0) marked on
the bottom axis, unstable or failed runs as red crosses on a shaded band above the plot's
errors (they have no trustworthy error). Each point is labelled with the varied settings.
Needs /usr/bin/python3 with matplotlib (scripts/install-deps.sh).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FIXED = {"case", "status", "healthy", "quantity", "measured", "error", "error_against", "pareto",
         "wall_s", "cpu_s", "peak_rss_mib", "particles", "steps", "max_density_variation",
         "energy_drift"}


def num(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("--cost", default="wall", choices=["wall", "cpu"], help="x axis: wall or CPU time")
    ap.add_argument("--label", default="", help="varied columns to label points with (default: all)")
    a = ap.parse_args()
    cost = "cpu_s" if a.cost == "cpu" else "wall_s"
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_study.py: no rows in " + a.csv)
    varied = [c for c in rows[0].keys() if c not in FIXED]
    if a.label:
        varied = [c for c in a.label.split(",") if c in varied]
    quantity = rows[0].get("quantity", "")
    against = next((r["error_against"] for r in rows if r.get("error")), "")

    def label(r):
        return ", ".join(f"{r[c]}" for c in varied)

    ok = [r for r in rows if r["healthy"] == "1" and not math.isnan(num(r["error"])) and num(r[cost]) > 0]
    zero = [r for r in rows if r["healthy"] == "1" and r["measured"] and not r["error"]]
    bad = [r for r in rows if r["healthy"] != "1"]
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    pos = [r for r in ok if num(r["error"]) > 0]
    errs = [num(r["error"]) for r in pos] or [1.0]
    lo, hi = min(errs), max(errs)
    ymin, ymax = lo / 3.0, hi * 3.0
    ymax_band = ymax * 10.0
    # Every run with a cost sets the range, failed ones too (a run refused at once costs ~0.1 s).
    walls = [num(r[cost]) for r in rows if num(r[cost]) > 0] or [1.0]
    xmin, xmax = min(walls) / 1.5, max(walls) * 1.5
    if pos:
        ax.scatter([num(r[cost]) for r in pos], errs, s=36, c="tab:blue", zorder=3,
                   label="healthy run")
    front = sorted([r for r in pos if r["pareto"] == "1"], key=lambda r: num(r[cost]))
    if front:
        ax.plot([num(r[cost]) for r in front], [num(r["error"]) for r in front], "-o",
                color="tab:green", lw=2, ms=9, mfc="none", zorder=4, label="Pareto front")
    for r in pos:
        ax.annotate(label(r), (num(r[cost]), num(r["error"])), textcoords="offset points",
                    xytext=(5, 4), fontsize=7)
    for r in zero:
        ax.scatter([num(r[cost])], [ymin * 1.2], marker="v", s=60, c="k", zorder=3)
        ax.annotate("reference: " + label(r), (num(r[cost]), ymin * 1.2), textcoords="offset points",
                    xytext=(5, 4), fontsize=7)
    if bad:
        ax.axhspan(ymax, ymax_band, color="tab:red", alpha=0.12, zorder=1)
        ax.text(xmin * 1.05, ymax * 1.3, "unstable / failed (no error)", color="tab:red", fontsize=8)
        for k, r in enumerate(bad):
            w = num(r[cost])
            w = w if w > 0 else xmin * 1.1
            y = ymax * (ymax_band / ymax) ** ((k + 0.5) / len(bad))  # one level each, log-spaced
            ax.scatter([w], [y], marker="x", s=60, c="tab:red", zorder=3,
                       label="unstable or failed" if k == 0 else None)
            ax.annotate(label(r) + " (" + r["status"].split(" - ")[0] + ")", (w, y), textcoords="offset points",
                        xytext=(5, -3), fontsize=7, color="tab:red")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax_band if bad else ymax)
    ax.set_xlabel(("CPU" if a.cost == "cpu" else "wall") + " time of the run (s)")
    ax.set_ylabel(f"error of {quantity}" + (f" vs {against}" if against else ""))
    ax.set_title(a.title or f"{quantity}: error against cost ({', '.join(varied)})", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
