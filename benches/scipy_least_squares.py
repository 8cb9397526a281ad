#!/usr/bin/env python3
"""scipy.optimize.least_squares on the design matrix of `cargo bench --bench estimate`.

The bench writes the fit's own design (the trunnion5 R-test, 4 320 readings x 20 unknowns)
and a right-hand side to <target>/criterion/estimate_design.csv; this script solves the same
linear least-squares problem J z = y with scipy (analytic Jacobian, as the Rust bench gives
its solver), times it the way criterion does (median of repeated runs), and checks that both
methods reach the same solution as numpy's lstsq.

    cargo bench --bench estimate -- linear_design_lm
    python3 benches/scipy_least_squares.py [PATH]
"""
import os
import sys
import time

import numpy as np
from scipy.optimize import least_squares


def main():
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(os.path.dirname(__file__), "..", "target"))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(target, "criterion", "estimate_design.csv")
    data = np.loadtxt(path, delimiter=",")
    design, y = data[:, :-1], data[:, -1]
    reference = np.linalg.lstsq(design, y, rcond=None)[0]
    fun = lambda z: design @ z - y
    jac = lambda z: design
    for method in ("lm", "trf"):
        times = []
        for _ in range(50):
            start = time.perf_counter()
            result = least_squares(fun, np.zeros(design.shape[1]), jac=jac, method=method)
            times.append(time.perf_counter() - start)
        error = np.max(np.abs(result.x - reference)) / np.max(np.abs(reference))
        print(f"scipy least_squares method={method}: median {np.median(times) * 1e3:.3f} ms "
              f"({design.shape[0]} x {design.shape[1]}, {result.nfev} evaluations, "
              f"max relative difference from lstsq {error:.1e})")


if __name__ == "__main__":
    main()
