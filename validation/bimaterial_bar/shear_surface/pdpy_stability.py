#!/usr/bin/env python3
"""Spectrum check of the strip stiffness (clamped layers removed) for the paper's force and the
corrected force (pdpy.py; Delta x = 0.01, nu = 1/3): asymmetry ||K - K^T|| / ||K||, smallest
|eigenvalues|, their real parts and the largest imaginary part (no zero-energy modes). Prints only."""
import numpy as np, pdpy
x = pdpy.grid(1.0, 0.1, 0.01)
fixed_pts = np.where((x[:, 0] <= 0.03) | (x[:, 0] >= 0.97))[0]
free = np.setdiff1d(np.arange(2 * len(x)), np.r_[2 * fixed_pts, 2 * fixed_pts + 1])
for mode in ("paper_w", "corrected"):
    K = pdpy.stiffness(x, 0.01, 3.015, 1.0, 1/3, mode)[free][:, free].toarray()
    print(mode, "asymmetry:", np.linalg.norm(K - K.T) / np.linalg.norm(K))
    ev = np.linalg.eigvals(K)
    ev = ev[np.argsort(np.abs(ev))]
    print(mode, "smallest |eig|:", np.round(np.abs(ev[:4]) * 1e4, 4), "x1e-4; min Re", ev.real.min(), "max |Im|/max|eig|",
          np.abs(ev.imag).max() / np.abs(ev).max())
