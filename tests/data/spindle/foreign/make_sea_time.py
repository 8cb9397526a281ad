"""Writes sea_time.csv: a spindle-analyser record sampled on TIME, not on the index, as a
commercial analyser (Lion Precision SEA style) exports it. Independent of mtwin: only the Python
standard library, its own physical model, its own conventions.

The export: free-text header lines (no probe geometry), two channels named x1 and y1 (one
radial station, probes along +X and +Y of the stator), columns in the exporter's own order
(y1_um, time_s, x1_um, revolution, angle_deg), revolutions numbered from 1, no speed column,
readings rounded to 1 nm, angles to 0.0001 deg (the encoder), CRLF line endings.

Sampling: a fixed rate of 25 600 Hz; the spindle turns at 6000 rpm (100 rev/s) on average with
a 0.3 % speed ripple at 70 Hz (not a multiple of the rotation), and the first sample comes
half a sample step after the index, so the samples fall off the 256-per-revolution index grid
and an analyser must resample. The angle of sample n, at t = n / fs, is

    phi(t) = Omega t + pi/M + A_phi sin(2 pi f_r t + psi_r),
    A_phi  = eps Omega / (2 pi f_r),   so  dphi/dt = Omega (1 + eps cos(2 pi f_r t + psi_r)),

with Omega = 2 pi 100 rad/s, M = 256, eps = 0.003. |A_phi| = 0.0043 rad is below half a
sample step (pi/M = 0.0123 rad), so every revolution still holds exactly 256 samples (the
table format asks for that) while no sample lies on the grid.

The physical model (um, theta = phi the true spindle angle, t the time), stator frame, at the
probed sphere's centre:

    X(theta, t) = e cos(theta + delta)                          artefact eccentricity, 1 UPR
                + p cos(theta + gamma)                           elliptical 1-UPR orbit
                + a2 cos(2 theta + alpha2)                       2-lobe: an elliptical 2-UPR
                + a3 cos(3 theta + alpha3)                       3-lobe
                + A_b cos(2 pi f_b t + psi_b)                    bearing line, forward whirl
                + N(0, sigma)                                    probe noise
    Y(theta, t) = e sin(theta + delta) + q sin(theta + gamma)
                + b2 sin(2 theta + alpha2) + b3 sin(3 theta + beta3)
                + A_b sin(2 pi f_b t + psi_b) + N(0, sigma)

The bearing line f_b = 440 Hz is 4.4 times the mean rotation frequency. The constants are
repeated in tests/it/cli_spindle.rs, which computes the closed forms from them.
Run: python3 make_sea_time.py  (in this folder)
"""
import math
import random

random.seed(20261126)

# Sampling.
F_ROT = 100.0  # mean rotation frequency, Hz (6000 rpm)
M = 256  # samples per mean revolution
FS = F_ROT * M  # 25 600 Hz
K = 11  # revolutions exported
EPS, F_R, PSI_R = 0.003, 70.0, 0.3  # speed ripple: relative amplitude, Hz, phase
OMEGA = 2 * math.pi * F_ROT
A_PHI = EPS * OMEGA / (2 * math.pi * F_R)
PHI0 = math.pi / M

# The model (um, rad).
E, DELTA = 4.0, 0.7
P, Q, GAMMA = 0.30, 0.18, -0.4
A2, B2, ALPHA2 = 0.40, 0.25, 0.5
A3, ALPHA3 = 0.22, 1.1
B3, BETA3 = 0.15, -0.6
A_B, F_B, PSI_B = 0.06, 440.0, 0.9
SIGMA = 0.004


def rows():
    for n in range(K * M):
        t = n / FS
        phi = OMEGA * t + PHI0 + A_PHI * math.sin(2 * math.pi * F_R * t + PSI_R)
        revolution, theta = divmod(phi, 2 * math.pi)
        assert int(revolution) == n // M, "a sample left its revolution"
        bearing = 2 * math.pi * F_B * t + PSI_B
        x = (
            E * math.cos(phi + DELTA)
            + P * math.cos(phi + GAMMA)
            + A2 * math.cos(2 * phi + ALPHA2)
            + A3 * math.cos(3 * phi + ALPHA3)
            + A_B * math.cos(bearing)
            + random.gauss(0.0, SIGMA)
        )
        y = (
            E * math.sin(phi + DELTA)
            + Q * math.sin(phi + GAMMA)
            + B2 * math.sin(2 * phi + ALPHA2)
            + B3 * math.sin(3 * phi + BETA3)
            + A_B * math.sin(bearing)
            + random.gauss(0.0, SIGMA)
        )
        yield y, t, x, int(revolution) + 1, math.degrees(theta)


with open("sea_time.csv", "w", newline="") as f:
    w = lambda s: f.write(s + "\r\n")
    w("# SEA data export")
    w("# Date: 2026-11-26 09:12")
    w("# Spindle speed: 6000 rpm (nominal)")
    w("# Sample rate: 25600 Hz, time-based sampling")
    w("# Target: sphere 25.4 mm, one radial station")
    w("# bandwidth_hz = 15000")
    w("y1_um,time_s,x1_um,revolution,angle_deg")
    for y, t, x, k, a in rows():
        w(f"{y:.3f},{t:.10f},{x:.3f},{k},{a:.4f}")
