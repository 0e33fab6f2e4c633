#!/usr/bin/env python3
"""Writes the synthetic deviation traces of scenarios/traces/ (python3 standard library only).

Deterministic: the same files on every machine (own linear congruential generator, fixed
formats). Rerun after editing:  python3 scenarios/traces/make_traces.py

First line: the directive "# headplan-trace: rows=deviation" (docs/batch.md): the rows are
deviations, whatever reads them. Columns: t_s, x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg: the measured head deviation
from the planned pose (IEC 61217 axes, +X left, +Y superior, +Z anterior), sampled at 10 Hz.

drift_10hz.csv  3 minutes (1800 rows): thermoplastic-mask drift of a few mm (the paper's
                introduction: masks drift 2-6 mm) that settles slowly, plus breathing
                motion (0.25 Hz, 0.1 mm) and 0.02 mm / 0.01 deg tracker noise.
nodding.csv     1 minute (600 rows): breathing-like nodding, pitch 0.8 deg at 0.25 Hz with
                the chin moving down (-Y, -Z) as the head pitches, no drift.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
DIRECTIVE = "# headplan-trace: rows=deviation"
HEADER = "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg"


class Lcg:
    """Numerical Recipes LCG: a fixed sequence of uniform numbers in [0, 1)."""

    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFF

    def uniform(self):
        self.state = (1664525 * self.state + 1013904223) & 0xFFFFFFFF
        return self.state / 4294967296.0

    def noise(self, amplitude):
        """Zero-mean triangular noise of the given half-width."""
        return amplitude * (self.uniform() - self.uniform())


def write(name, rows):
    path = os.path.join(HERE, name)
    with open(path, "w", newline="\n") as f:
        f.write(DIRECTIVE + "\n" + HEADER + "\n")
        for r in rows:
            f.write("%.1f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n" % r)


def drift():
    rng = Lcg(20200531)
    rows = []
    for i in range(1800):
        t = i / 10.0
        settle = 1.0 - math.exp(-t / 60.0)
        breath = math.sin(2.0 * math.pi * 0.25 * t)
        x = 2.0 * settle + rng.noise(0.02)
        y = 1.2 * t / 180.0 + rng.noise(0.02)
        z = -1.5 * (1.0 - math.exp(-t / 90.0)) + 0.1 * breath + rng.noise(0.02)
        pitch = 0.5 * settle + 0.05 * breath + rng.noise(0.01)
        roll = 0.2 * t / 180.0 + rng.noise(0.01)
        yaw = -0.3 * settle + rng.noise(0.01)
        rows.append((t, x, y, z, pitch, roll, yaw))
    return rows


def nodding():
    rng = Lcg(7)
    rows = []
    for i in range(600):
        t = i / 10.0
        s = math.sin(2.0 * math.pi * 0.25 * t)
        pitch = 0.8 * s + rng.noise(0.01)
        y = -0.3 * s + rng.noise(0.02)
        z = -0.4 * s + rng.noise(0.02)
        rows.append((t, rng.noise(0.02), y, z, pitch, rng.noise(0.01), rng.noise(0.01)))
    return rows


if __name__ == "__main__":
    write("drift_10hz.csv", drift())
    write("nodding.csv", nodding())
