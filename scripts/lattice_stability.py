#!/usr/bin/python3
"""Is a particle lattice stable under a positive pressure with the symmetric SPH pressure force?
(docs/fluid.md "Water at rest on the lattice").

With Eq. 5.2b at a uniform pressure p every particle is driven by
    a_a = -(2 p V / rho) grad_a sum_b W(x_a - x_b),
i.e. down the gradient of its own kernel sum. Displace the lattice by a plane wave
u_b = n e^{i k.r_b}: the restoring matrix is D(k) = sum_b H(W)(r_b) (1 - cos k.r_b) (H the
Hessian of W). A transverse wave (n perpendicular to k) changes no density to first order, so
the equation of state adds nothing to it: with n.D(k).n < 0 it grows at
    sigma = sqrt(-2 n.D.n) sqrt(p / rho) / dx        (dx = 1 units for D).
Prints the least stable transverse mode of the square lattice (and the hexagonal one of the
same area per particle) for the 2D kernels and a few h/dx.

Usage: lattice_stability.py [h/dx ...]"""
import sys

import numpy as np


def wendland_c2(r, h):
    q = r / h
    return np.where(q < 2, 7 / (4 * np.pi * h * h) * (1 - q / 2) ** 4 * (2 * q + 1), 0)


def quintic_spline(r, h):
    q = r / h
    s = 7 / (478 * np.pi * h * h)
    return s * (np.where(q < 3, (3 - q) ** 5, 0) - 6 * np.where(q < 2, (2 - q) ** 5, 0)
                + 15 * np.where(q < 1, (1 - q) ** 5, 0))


def cubic_spline(r, h):
    q = r / h
    s = 10 / (7 * np.pi * h * h)
    return s * np.where(q < 1, 1 - 1.5 * q ** 2 + 0.75 * q ** 3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0))


def hessian(w, h, x, y, e=1e-4):
    f = lambda a, b: w(np.hypot(a, b), h)
    xx = (f(x + e, y) - 2 * f(x, y) + f(x - e, y)) / e ** 2
    yy = (f(x, y + e) - 2 * f(x, y) + f(x, y - e)) / e ** 2
    xy = (f(x + e, y + e) - f(x + e, y - e) - f(x - e, y + e) + f(x - e, y - e)) / (4 * e * e)
    return xx, yy, xy


def lattice(kind):
    i = np.arange(-10, 11)
    a, b = np.meshgrid(i, i)
    a, b = a.ravel().astype(float), b.ravel().astype(float)
    if kind == "square":
        x, y = a, b
    else:  # hexagonal, one particle per unit area
        s = np.sqrt(2 / np.sqrt(3))
        x, y = s * (a + 0.5 * b), s * np.sqrt(3) / 2 * b
    keep = ~((a == 0) & (b == 0))
    return x[keep], y[keep]


def least_stable(w, h, kind):
    x, y = lattice(kind)
    xx, yy, xy = hessian(w, h, x, y)
    best = (np.inf, None)
    for kx in np.linspace(-np.pi, np.pi, 25):
        for ky in np.linspace(0, np.pi, 13):
            if kx == 0 and ky == 0:
                continue
            c = 1 - np.cos(kx * x + ky * y)
            n = np.array([-ky, kx]) / np.hypot(kx, ky)
            d = np.array([[np.sum(xx * c), np.sum(xy * c)], [np.sum(xy * c), np.sum(yy * c)]])
            v = n @ d @ n
            if v < best[0]:
                best = (v, (kx, ky))
    return best


if __name__ == "__main__":
    hs = [float(a) for a in sys.argv[1:]] or [1.0, 1.2, 1.3, 1.5, 2.0]
    for name, w in [("wendland_c2", wendland_c2), ("quintic_spline", quintic_spline), ("cubic_spline", cubic_spline)]:
        for kind in ["square", "hex"]:
            for h in hs:
                v, k = least_stable(w, h, kind)
                grow = "unstable: sigma = %.3f sqrt(p/rho)/dx" % np.sqrt(-2 * v) if v < -1e-6 else "stable"
                print("%-15s %-6s h/dx %.2f  least stable transverse n.D.n %+.3e at k dx = (%.2f, %.2f)  %s"
                      % (name, kind, h, v, k[0], k[1], grow))
