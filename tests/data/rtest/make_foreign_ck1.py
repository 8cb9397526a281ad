"""Writes foreign_ck1.csv: an R-test export made by an independent simulator, not by mtwin.

A table-table machine, C turning at A = 0, the C axis line displaced by (15, -10) um from where
the controller believes it; the sphere 100 mm off the axis at 40 deg. The table turns the sphere
about the true line, p' = d + R(p - d); the controller expects R p; the nest, following R p,
sees the tool relative to the sphere as -(p' - R p). Readings are zeroed at the first pose,
Gaussian noise of 0.15 um is added (seeded) and values are rounded to 0.1 um, as a vendor export
is, with free-text header lines. Run: python3 make_foreign_ck1.py
"""
import math
import random

random.seed(20261125)
dx, dy = 15e-6, -10e-6
r, phi = 0.1, math.radians(40)
p = (r * math.cos(phi), r * math.sin(phi))
rows = []
first = None
for k in range(73):
    c = math.radians(5 * k)
    # C turns the table about -Z: in the machine frame the rotation is Rot(z, -C).
    cs, sn = math.cos(-c), math.sin(-c)

    def rot(v):
        return (cs * v[0] - sn * v[1], sn * v[0] + cs * v[1])

    rp = rot(p)
    q = rot((p[0] - dx, p[1] - dy))
    actual = (dx + q[0], dy + q[1])
    dev = (-(actual[0] - rp[0]), -(actual[1] - rp[1]), 0.0)
    if first is None:
        first = dev
    dev = [(dev[i] - first[i]) * 1e6 + random.gauss(0, 0.15) for i in range(3)]
    rows.append((5 * k, dev))
with open("foreign_ck1.csv", "w") as f:
    f.write("# Rotary axis check export\n# Operator: QA\n# Sphere: 25.4 mm, offset 100 mm\n")
    f.write("test,c_deg,dz_um,dy_um,dx_um\n")
    for c, d in rows:
        f.write(f"C circle,{c:.1f},{d[2]:.1f},{d[1]:.1f},{d[0]:.1f}\n")
