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

The horizon-planning traces (docs/horizon.md), planned with rate limits that bind:
step.csv        30 s (300 rows): a patient shifting three times (sudden steps of 1-2 mm and
                about 1 deg, held), 0.02 mm / 0.01 deg noise.
breathing.csv   60 s (600 rows): breathing-like periodic motion, 1.5 mm vertical, 0.6 mm
                longitudinal and 1 deg pitch at 0.25 Hz, with a slower 0.05 Hz component.
drift_long.csv  10 minutes (about 6000 rows), recorded-style: IRREGULAR sampling (10 Hz with
                +-20 ms jitter and a dropped stretch of rows every 50 s), a mask drift of
                about 3 mm that settles, breathing, two small shifts and tracker noise.
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


def write(name, rows, time_format="%.1f"):
    path = os.path.join(HERE, name)
    with open(path, "w", newline="\n") as f:
        f.write(DIRECTIVE + "\n" + HEADER + "\n")
        for r in rows:
            f.write((time_format + ",%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n") % r)


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


def step():
    rng = Lcg(14)
    rows = []
    # (start time s, x, y, z mm, pitch, roll, yaw deg): the pose held from that time on
    shifts = [(0.0, 0, 0, 0, 0, 0, 0), (5.0, 2.0, 0, -1.5, 0, 0, 0),
              (12.0, 2.0, 0, -1.5, 1.0, 0, -0.8), (20.0, 0.5, 1.0, -0.5, 0.3, 0.4, -0.2)]
    for i in range(300):
        t = i / 10.0
        pose = [p for p in shifts if p[0] <= t][-1][1:]
        noise = [rng.noise(0.02) for _ in range(3)] + [rng.noise(0.01) for _ in range(3)]
        rows.append((t,) + tuple(p + e for p, e in zip(pose, noise)))
    return rows


def breathing():
    rng = Lcg(25)
    rows = []
    for i in range(600):
        t = i / 10.0
        s = math.sin(2.0 * math.pi * 0.25 * t)
        slow = math.sin(2.0 * math.pi * 0.05 * t)
        rows.append((t, 0.3 * slow + rng.noise(0.02), -0.6 * s + rng.noise(0.02),
                     1.5 * s + 0.3 * slow + rng.noise(0.02), 1.0 * s + rng.noise(0.01),
                     0.2 * slow + rng.noise(0.01), rng.noise(0.01)))
    return rows


def drift_long():
    rng = Lcg(600)
    rows = []
    t = 0.0
    i = 0
    while t < 600.0:
        settle = 1.0 - math.exp(-t / 120.0)
        breath = math.sin(2.0 * math.pi * 0.25 * t)
        shift = (1.0 if t >= 200.0 else 0.0) - (0.6 if t >= 420.0 else 0.0)
        rows.append((t, 3.0 * settle + 0.5 * shift + rng.noise(0.03),
                     0.8 * t / 600.0 + rng.noise(0.03),
                     -2.0 * settle + 0.15 * breath - 0.4 * shift + rng.noise(0.03),
                     0.6 * settle + 0.08 * breath + 0.3 * shift + rng.noise(0.015),
                     0.3 * t / 600.0 + rng.noise(0.015),
                     -0.4 * settle + rng.noise(0.015)))
        i += 1
        dt = 0.1 + rng.noise(0.02)
        if i % 500 == 0:
            dt += 0.4  # the tracker dropped a few frames
        t += dt
    return rows


if __name__ == "__main__":
    write("drift_10hz.csv", drift())
    write("nodding.csv", nodding())
    write("step.csv", step())
    write("breathing.csv", breathing())
    write("drift_long.csv", drift_long(), "%.3f")
