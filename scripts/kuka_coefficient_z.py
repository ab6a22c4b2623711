#!/usr/bin/env python3
"""Run-to-run agreement of the effect coefficients on the KUKA LWR4+ logs (issue 45).

Fits measurements_1.csv and measurements_2.csv separately with `inertial identify --json
--effects offset,viscous,coulomb` and prints, for each of the 21 effect coefficients (3 per joint),
z = |c1 - c2| / sqrt(std1^2 + std2^2), then their median and max. The two runs repeat one
trajectory, so the same coefficient fitted on each should differ by about its std: with calibrated
stds z is |N(0, 1)| (median 0.67, above 3 once in 370).

Usage: scripts/kuka_coefficient_z.py [INERTIAL_BINARY] [DATA_DIR]
(defaults: build/inertial, ../shared/data/kuka_lwr4 beside the checkout). Exit 77 if the data are absent.
"""
import json
import math
import os
import statistics
import subprocess
import sys

here = os.path.dirname(os.path.abspath(__file__))
binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "build", "inertial")
data = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "..", "..", "shared", "data", "kuka_lwr4")
if not os.path.isfile(os.path.join(data, "measurements_1.csv")):
    print(f"no KUKA data in {data}", file=sys.stderr)
    sys.exit(77)


def fit(run):
    out = subprocess.run([binary, "identify", "--model", os.path.join(data, "kuka_lwr4.urdf"), "--data",
                          os.path.join(data, f"measurements_{run}.csv"), "--effects", "offset,viscous,coulomb",
                          "--json"], check=True, capture_output=True, text=True).stdout
    j = json.loads(out)
    coefficients = {}
    for e in j["effects"]:
        for name, value in e["values"].items():
            sd = e["std"][name]
            coefficients[f'{e["effect"]}@{e["joint"]}.{name}'] = (value, float(sd))
    return coefficients, j.get("uncertainty_blocks")


c1, b1 = fit(1)
c2, b2 = fit(2)
zs = []
for key in c1:
    (v1, s1), (v2, s2) = c1[key], c2[key]
    z = abs(v1 - v2) / math.sqrt(s1 * s1 + s2 * s2)
    zs.append(z)
    print(f"{key:32s} run1 {v1:+.5g} +- {s1:.3g}   run2 {v2:+.5g} +- {s2:.3g}   z {z:.2f}")
if b1:
    print(f"time blocks: run 1 {b1}, run 2 {b2}")
print(f"{len(zs)} coefficients: median z {statistics.median(zs):.2f}, max z {max(zs):.2f}")
