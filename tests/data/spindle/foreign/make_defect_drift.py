"""Writes defect_drift.csv: a spindle-analyser record made with a physical model other than
mtwin's, for `mtwin discover spindle`. Independent of mtwin: only the Python standard library.

The spindle turns at 300 rpm (5 rev/s) for 40 revolutions (8 s), sampled on the index at 128
samples a revolution; three probes: x1 and y1 on one radial station (artefact motion along +X
and +Y increases them), z on the axis. Readings are rounded to 1 nm, as an analyser's export.

What is in it (um; theta the spindle angle, u the turns since the first index, t the time):

  - set-up: the sphere 2.5 um off centre (1 UPR) and an elliptical 2-UPR orbit (the base model);
  - a 5-lobed synchronous error motion, 0.08 um in X and Y (hidden: a harmonic beyond the base);
  - an outer-race defect of a 6205-size bearing (9 balls of 7.94 mm on a 39.04 mm pitch, 0 deg
    contact): BPFO = 4.5 (1 - 7.94/39.04) = 3.5848 per revolution from the geometry; the cage
    slips 1 %, so the balls pass the defect at f_d = 0.99 * 3.5848 = 3.5490 per revolution. Each
    pass is an impact, not a sinusoid: a half-sine bump of 0.06 um lasting 20 % of the pass
    period, in the load direction (X). Its spectrum has lines at f_d, 2 f_d, 3 f_d ...: the
    fundamental's amplitude is 0.06 * (2 w / pi) * |cos(pi w)| / |1 - 4 w^2| with w = 0.2 (the
    bump's fraction of the period) = 0.0079 * ... computed in the test, not here;
  - a thermal transient of the axial reading: z grows by 0.30 um * (1 - exp(-t / 3 s)) (the
    probe holder settling after the spindle starts: a first-order approach, not a line);
  - probe noise 3 nm (Gaussian), rounding to 1 nm.

The constants are repeated in tests/it/discovery_spindle.rs, which computes what discovery must find.
Run: python3 make_defect_drift.py  (in this folder)
"""
import math
import random

random.seed(20261125)

RPM = 300.0
M = 128
K = 40
F_ROT = RPM / 60.0
E, DELTA = 2.5, 0.3
P2, Q2, ALPHA2 = 0.20, 0.12, 0.8
A5, ALPHA5 = 0.08, -0.5
F_D = 0.99 * 4.5 * (1.0 - 7.94 / 39.04)
BUMP, WIDTH = 0.06, 0.2
Z_DRIFT, TAU = 0.30, 3.0
SIGMA = 0.003


def bump(u):
    """The impact train at turns u: a half-sine of height BUMP over WIDTH of each pass."""
    phase = (u * F_D) % 1.0
    return BUMP * math.sin(math.pi * phase / WIDTH) if phase < WIDTH else 0.0


def rows():
    for n in range(K * M):
        revolution, m = divmod(n, M)
        theta = 2 * math.pi * m / M
        u = n / M
        t = u / F_ROT
        x = (
            E * math.cos(theta + DELTA)
            + P2 * math.cos(2 * theta + ALPHA2)
            + A5 * math.cos(5 * theta + ALPHA5)
            + bump(u)
            + random.gauss(0.0, SIGMA)
        )
        y = (
            E * math.sin(theta + DELTA)
            + Q2 * math.sin(2 * theta + ALPHA2)
            + A5 * math.sin(5 * theta + ALPHA5)
            + random.gauss(0.0, SIGMA)
        )
        z = 0.05 + Z_DRIFT * (1.0 - math.exp(-t / TAU)) + random.gauss(0.0, SIGMA)
        yield revolution, math.degrees(theta), t, x, y, z


with open("defect_drift.csv", "w", newline="") as f:
    f.write("# spindle record exported by a third-party analyser\n")
    f.write("revolution,angle_deg,time_s,speed_rpm,x1_um,y1_um,z_um\n")
    for k, a, t, x, y, z in rows():
        f.write(f"{k},{a:.4f},{t:.6f},{RPM:.1f},{x:.3f},{y:.3f},{z:.3f}\n")
