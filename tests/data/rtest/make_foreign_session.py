"""Writes foreign_session.csv and foreign_session_clean.csv: R-test exports of a session of four
tests made by an independent simulator, not by mtwin, with three faults hidden in the first.

A table-table machine at A = 0: C turns the table about -Z (in the machine frame the table
turns by Rot(z, -C)); the C axis line is displaced by (15, -10) um from where the controller
believes it; the sphere sits 100 mm off the axis at 40 deg. Each test turns C from 0 to 360 deg
and back in 10 deg steps, a pose every 5 s, the nest zeroed at the test's first pose; the tests
follow one another with a minute between them, and each row's time_s is the time since its
test's start. Gaussian noise of 0.15 um is added (seeded) and values are rounded to 0.1 um, as
a vendor export is, with free-text header lines.

The faults of foreign_session.csv, each by a physical model of its own (not mtwin's):
  - an elliptical journal in C's bearing: the table's centre moves along X by
    1.5 um * cos(2*theta + 30 deg), theta the table's actual angle (2 per turn);
  - a worm gear with 20 urad of backlash and a compliant mesh: the table lags the command by
    +10 urad travelling up and -10 urad travelling down, and after a reversal the lag crosses
    over as exp(-s / 3 deg) of the travel s since the reversal (not a step);
  - the spindle warming: the tool tip moves by D * (1 - exp(-t / 120 min)) over the session's
    time t, D = (20, 0, 60) um, i.e. 10 and 30 um/h at the start, slowing by 18 % over the
    session (not a constant rate).
foreign_session_clean.csv is the same session with the line displacement only. The nest reads
the tool relative to the sphere: the tool's drift minus the sphere's displacement from where
the controller puts it. Run: python3 make_foreign_session.py
"""
import math
import random

DX, DY = 15e-6, -10e-6
R, PHI = 0.1, math.radians(40)
P = (R * math.cos(PHI), R * math.sin(PHI))
WOBBLE, WOBBLE_PHASE = 1.5e-6, math.radians(30)
BACKLASH, MESH = 20e-6, math.radians(3)
DRIFT, TAU = (20e-6, 0.0, 60e-6), 120 * 60.0
DWELL, PAUSE = 5.0, 60.0
STEPS = list(range(0, 361, 10)) + list(range(350, -1, -10))


def rot(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def session(faults, seed):
    random.seed(seed)
    rows = []
    start = 0.0
    for test in range(4):
        # The table arrived at 0 travelling up (the mesh settled).
        direction, since = 1, math.inf
        first = None
        previous = 0.0
        for k, c_deg in enumerate(STEPS):
            command = math.radians(c_deg)
            move = command - previous
            if move != 0.0:
                new = 1 if move > 0 else -1
                if new != direction:
                    direction, since = new, 0.0
                since += abs(move)
            previous = command
            lag = 0.0
            if faults:
                lag = direction * BACKLASH * (0.5 - math.exp(-since / MESH))
            actual = command - lag
            # The table turns about the true line (DX, DY) by Rot(z, -actual); the controller
            # puts the tool where the nominal table would carry the sphere, Rot(z, -command) P.
            q = rot((P[0] - DX, P[1] - DY), -actual)
            sphere = [DX + q[0], DY + q[1], 0.0]
            if faults:
                sphere[0] += WOBBLE * math.cos(2 * actual + WOBBLE_PHASE)
            nominal = rot(P, -command)
            t = DWELL * k
            session_time = start + t
            tool = [0.0, 0.0, 0.0]
            if faults:
                tool = [d * (1 - math.exp(-session_time / TAU)) for d in DRIFT]
            dev = (
                tool[0] - (sphere[0] - nominal[0]),
                tool[1] - (sphere[1] - nominal[1]),
                tool[2] - sphere[2],
            )
            if first is None:
                first = dev
            dev = [(dev[i] - first[i]) * 1e6 + random.gauss(0, 0.15) for i in range(3)]
            rows.append((f"C out and back {test + 1}", t, c_deg, dev))
        start += DWELL * (len(STEPS) - 1) + PAUSE
    return rows


for name, faults, seed in [
    ("foreign_session.csv", True, 20261201),
    ("foreign_session_clean.csv", False, 20261202),
]:
    with open(name, "w") as f:
        f.write("# Rotary axis check export\n# Operator: QA, session of four C checks\n")
        f.write("# Sphere: 25.4 mm, offset 100 mm\n")
        f.write("test,time_s,c_deg,dz_um,dy_um,dx_um\n")
        for test, t, c, d in session(faults, seed):
            f.write(f"{test},{t:.1f},{c:.1f},{d[2]:.1f},{d[1]:.1f},{d[0]:.1f}\n")
