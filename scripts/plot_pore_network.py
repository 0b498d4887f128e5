#!/usr/bin/python3
"""Picture of the SPH drainage of the pore network (issue 14 D4, docs/fluid.md "Pore network
against invasion percolation") from the files of tests/validation/test_fluid_pore_network_long.cpp:
<build>/fluid_pore_network_<tag>.csv (t, Pc, gas fraction of every body and throat, every 1 ms)
and <build>/fluid_pore_network_<tag>_gas.txt (gas particles: t, x, y in voxels of the image).

    /usr/bin/python3 scripts/plot_pore_network.py docs/img/fluid_pore_network_sph.png \
        build/fluid_pore_network_ramp="tau 1.2 s" build/fluid_pore_network_tau0.4_pc80_gamma0.05="tau 0.4 s"

one row per run (<csv base>=<title>).

Left: the network (grey solid) and the gas at breakthrough, each throat crossed labelled with its
SPH rank (s#) and its IP rank (ip#, to breakthrough). Right: every invaded body's gas fraction
against time and the drive Pc (dashed) against the throats' exit pressures 2 gamma / w (dotted).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    out, runs = sys.argv[1], sys.argv[2:]
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    net = json.load(open(os.path.join(root, "data", "pore_network_seed14.json")))
    nx, ny = net["size"]
    raw = open(os.path.join(root, "data", "pore_network_seed14.raw"), "rb").read()
    img = [[raw[y * nx + x] for x in range(nx)] for y in range(ny)]
    fig, axes = plt.subplots(len(runs), 2, figsize=(14, 5.6 * len(runs)), gridspec_kw={"width_ratios": [1.35, 1]},
                             squeeze=False)
    for (ax, bx), run in zip(axes, runs):
        base, _, title = run.partition("=")
        one(net, img, base, title or os.path.basename(base), ax, bx)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


def one(net, img, base, title, ax, bx):
    nx, ny = net["size"]
    rows = [list(map(float, l.split(","))) for l in open(base + ".csv") if not l.startswith("#")]
    t = [r[0] for r in rows]
    pc = [r[1] for r in rows]
    outlet = [r[2] for r in rows]
    nb = len(net["bodies"])
    nt = len(net["throats"])
    fb = [[r[3 + k] for r in rows] for k in range(nb)]
    ft = [[r[3 + nb + k] for r in rows] for k in range(nt)]
    # events as the test reads them: a body is invaded when its gas fraction passes 0.5, through
    # the widest throat to the gas cluster filled with gas; breakthrough at > 100 gas particles in
    # the outlet reservoir
    order, border, tbreak, gasn = [], [], None, {-1}

    def cross(node, j):
        # the throat filled with gas to its exit (> 0.8) and widest, else the one with the most gas
        def key(tid):
            full = ft[tid][j] > 0.8
            return (full, net["throats"][tid]["width"] if full else 0, ft[tid][j])
        best = None
        for th in net["throats"]:
            other = th["b"] if th["a"] == node else th["a"] if th["b"] == node else None
            if other is None or other not in gasn:
                continue
            if best is None or key(th["id"]) > key(best):
                best = th["id"]
        if best is not None:
            order.append(best)

    for j in range(len(t)):
        if tbreak is not None:
            break
        now = sorted([k for k in range(nb) if k not in border and fb[k][j] > 0.5], key=lambda k: -fb[k][j])
        for k in now:
            border.append(k)
            cross(k, j)
            gasn.add(k)
        if outlet[j] > 100:
            tbreak = t[j]
            cross(-2, j)
    ip_rank = {}
    # IP order to breakthrough: the prefix of ip_order (barrier) up to the first outlet throat
    for k, tid in enumerate(net["ip_order"]):
        ip_rank[tid] = k + 1
        if net["throats"][tid]["b"] == -2:
            break
    gas = {}
    for line in open(base + "_gas.txt"):
        a = line.split()
        gas.setdefault(float(a[0]), []).append((float(a[1]), float(a[2])))
    times = sorted(gas)
    t_show = [tt for tt in times if tbreak is None or tt <= tbreak + 1e-9]
    t_show = t_show[-1] if t_show else times[-1]

    ax.imshow(img, cmap="Greys", origin="lower", interpolation="nearest", vmin=0, vmax=1.6, alpha=0.9)
    xs = [p[0] for p in gas[t_show]]
    ys = [p[1] for p in gas[t_show]]
    ax.scatter(xs, ys, s=0.6, c="tab:orange", lw=0, label=f"gas at t = {1000 * t_show:.0f} ms")
    for th in net["throats"]:
        x0, x1, y0, y1 = th["box"]
        tid = th["id"]
        s = f"t{tid} w{th['width']}"
        if tid in order:
            s += f"\ns#{order.index(tid) + 1}"
        if tid in ip_rank:
            s += f" ip#{ip_rank[tid]}"
        col = "red" if tid in order else ("blue" if tid in ip_rank else "dimgray")
        ax.text((x0 + x1) / 2, (y0 + y1) / 2, s, ha="center", va="center", fontsize=6, color=col)
    ax.set_xlim(min(xs + [0.0]) - 2, nx + 2)
    ax.set_ylim(-2, ny + 2)
    ax.set_title(title + ": gas (orange) at breakthrough; s# SPH rank, ip# IP rank (to breakthrough)", fontsize=9)
    ax.legend(loc="upper right", fontsize=7, markerscale=8)
    ax.set_xlabel("x (voxels = dx = 0.1 mm)")
    # right: the invaded bodies' gas fractions against time, the drive on the second axis
    jend = len(t) if tbreak is None else min(len(t), next(j for j in range(len(t)) if t[j] >= tbreak) + 40)
    tm = [1000 * v for v in t[:jend]]
    for k in border:
        bx.plot(tm, fb[k][:jend], lw=1.2, label=f"body {k}")
    bx.set_xlabel("t (ms)")
    bx.set_ylabel("gas fraction of the body")
    bx.set_ylim(-0.02, 1.05)
    bx.axhline(0.5, color="k", lw=0.5)
    cx = bx.twinx()
    cx.plot(tm, pc[:jend], "k--", lw=1, label="drive Pc")
    for w in sorted({net["throats"][k]["width"] for k in order} | {8, 7}):
        cx.axhline(1000.0 / w, color="gray", ls=":", lw=0.8)
        cx.text(tm[0], 1000.0 / w, f" exit w{w}: {1000.0 / w:.0f} Pa", fontsize=6, va="bottom", color="gray")
    cx.set_ylabel("drive Pc = rho f Lx + 2 gamma cos(theta) / H (Pa)")
    bx.legend(fontsize=7, loc="center left")
    bx.set_title("bodies invaded up to breakthrough; dotted: exit pressures 2 gamma / w", fontsize=9)
    print(base, "throats", order, "bodies", border, "breakthrough", tbreak)


if __name__ == "__main__":
    main()
