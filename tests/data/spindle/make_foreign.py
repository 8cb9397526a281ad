"""Writes foreign_sea.csv: a spindle-analyser export made by an independent model, not by mtwin,
in the style of a commercial analyser's data export: free-text header lines, no probe geometry
in the preamble (only the station separation), channels named x1, y1 (lower sphere), x2, y2
(upper sphere, 60 mm above) and z (axial), columns in the exporter's own order, revolutions
numbered from 1, no speed column (3000 rpm, stated only in free text), readings rounded to
1 nm, CRLF line endings.

The model (um, theta the spindle angle): each sphere's centre runs on a circle of radius e_i
(eccentricity, phase p_i) with a 2-UPR and a 5-UPR synchronous term; the axis tilts so station
2 moves differently; a seeded Gaussian asynchronous part of 0.02 um on every channel; the
axial channel has a 3-UPR term and a slow thermal growth of 0.01 um per revolution.
32 samples per revolution, 4 revolutions; 3000 rpm = 50 rev/s, so samples 0.000625 s apart.
Run: python3 make_foreign.py
"""
import math
import random

random.seed(20261125)
M, K = 32, 4
dt = 1.0 / (50 * M)
rows = []
for k in range(K):
    for m in range(M):
        t = (k * M + m) * dt
        th = 2 * math.pi * m / M
        g = lambda: random.gauss(0, 0.02)
        x1 = 4.0 * math.cos(th + 0.4) + 0.12 * math.cos(2 * th) + 0.05 * math.sin(5 * th) + g()
        y1 = 4.0 * math.sin(th + 0.4) + 0.12 * math.sin(2 * th) - 0.05 * math.cos(5 * th) + g()
        x2 = 4.6 * math.cos(th + 0.5) + 0.10 * math.cos(2 * th + 0.2) + g()
        y2 = 4.6 * math.sin(th + 0.5) + 0.10 * math.sin(2 * th + 0.2) + g()
        z = 0.08 * math.cos(3 * th) + 0.01 * (k + m / M) + g()
        rows.append((t, z, 360.0 * m / M, y2, x2, k + 1, y1, x1))
with open("foreign_sea.csv", "w", newline="") as f:
    w = lambda s: f.write(s + "\r\n")
    w("# SEA data export")
    w("# Date: 2026-11-20 14:32")
    w("# Spindle speed: 3000 rpm")
    w("# Target: two spheres, 25.4 mm")
    w("# station_separation_mm = 60")
    w("# bandwidth_hz = 15000")
    w("time_s,z_um,angle_deg,y2_um,x2_um,revolution,y1_um,x1_um")
    for t, z, a, y2, x2, k, y1, x1 in rows:
        w(f"{t:.6f},{z:.3f},{a:.3f},{y2:.3f},{x2:.3f},{k},{y1:.3f},{x1:.3f}")
