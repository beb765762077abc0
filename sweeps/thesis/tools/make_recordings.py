#!/usr/bin/env python3
"""Writes the two SYNTHETIC stand-ins for the thesis's Flock-of-Birds recordings (section 6.2.3).

The thesis's recordings are not available. These are made from documented human-movement
models, shaped like the thesis's two tasks, sampled like its tracker (100 Hz) with white
position noise, in the CSV form `trajectory.recorded` reads (header x,y,z; metres; world frame
of models/dlr_lwr3.urdf):

  picking_synthetic.csv  reaching several positions on the floor and jumping between them:
                         minimum-jerk transfers (Flash & Hogan 1985) between seeded floor
                         positions, lifted over a via height, with dwell times at each position.
  sphere_synthetic.csv   a smooth closed path on a sphere about 30 cm above the surface, timed
                         by the two-thirds power law (Lacquaniti, Terzuolo & Viviani 1983),
                         starting and ending at rest.

Standard library only; seeded and deterministic (own Box-Muller on random.random()).
Usage: python3 sweeps/thesis/tools/make_recordings.py [OUTPUT_DIR]  (default sweeps/thesis/data)
"""
import math
import os
import random
import sys

SAMPLE_RATE = 100.0        # Hz, the Flock of Birds rate the thesis states
NOISE_SIGMA = 0.0005       # m, per axis, white Gaussian (our choice; the thesis gives no figure)
BOX_MIN = (0.20, 0.20, 0.00)  # m, the thesis's reaching region (section 6.2.2)
BOX_MAX = (0.70, 0.70, 0.50)
DECIMALS = 5               # 0.01 mm in the CSV

# Picking task
PICK_SEED = 20081
PICK_POSITIONS = 8             # floor positions visited in turn
PICK_FLOOR_Z = 0.05            # m, tool tip height at a floor position
PICK_LIFT = 0.12               # m, lift above the floor between positions
PICK_RADIUS = (0.82, 0.93)     # m, horizontal distance from the base axis: floor points a 3-DOF arm (joints 1, 2, 4) reaches within its limits
PICK_XY = (0.30, 0.68)         # m, x and y range of the floor positions
PICK_MIN_SPACING = 0.12        # m between consecutive positions (a third of it to any earlier one)
PICK_DWELL = (0.4, 0.8)        # s, uniform
PICK_TRANSFER = (0.7, 1.6)     # s: duration = a + b * distance (m), a Fitts-like rule

# Sphere task
SPHERE_SEED = 20082
SPHERE_CENTRE = (0.50, 0.45, 0.30)  # m: about 30 cm above the surface
SPHERE_RADIUS = 0.10                # m
SPHERE_WAVES = 3                    # latitude oscillations per turn
SPHERE_LATITUDE = 0.45              # rad, amplitude of the latitude wave
SPHERE_LOOPS = 3
SPHERE_PERIOD = 5.0                 # s per loop at power-law speed
SPHERE_RAMP = 1.5                   # s to start from and return to rest


def minimum_jerk(tau):
    """Position fraction of a minimum-jerk movement at normalised time tau in [0, 1]."""
    tau = min(max(tau, 0.0), 1.0)
    return tau ** 3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)


class Noise:
    """Seeded white Gaussian noise (Box-Muller on random.random(), the same on every Python 3)."""

    def __init__(self, seed):
        self.rng = random.Random(seed)
        self.spare = None

    def normal(self):
        if self.spare is not None:
            value, self.spare = self.spare, None
            return value
        u1 = 1.0 - self.rng.random()  # (0, 1]
        u2 = self.rng.random()
        radius = math.sqrt(-2.0 * math.log(u1))
        self.spare = radius * math.sin(2.0 * math.pi * u2)
        return radius * math.cos(2.0 * math.pi * u2)


def picking_path():
    """Clean picking motion sampled at SAMPLE_RATE: a list of (x, y, z)."""
    rng = random.Random(PICK_SEED)
    positions = []
    attempts = 0
    while len(positions) < PICK_POSITIONS:
        attempts += 1
        if attempts > 100000:
            raise SystemExit("picking: cannot place %d floor positions with these constants" % PICK_POSITIONS)
        x = rng.uniform(*PICK_XY)
        y = rng.uniform(*PICK_XY)
        radius = math.hypot(x, y)
        if not PICK_RADIUS[0] <= radius <= PICK_RADIUS[1]:
            continue
        if positions and math.hypot(x - positions[-1][0], y - positions[-1][1]) < PICK_MIN_SPACING:
            continue
        if any(math.hypot(x - p[0], y - p[1]) < PICK_MIN_SPACING / 3 for p in positions):
            continue
        positions.append((x, y, PICK_FLOOR_Z))
    # Piecewise motion: dwell at a position, then a transfer to the next one.
    pieces = []
    for i, position in enumerate(positions):
        pieces.append(("dwell", position, position, rng.uniform(*PICK_DWELL)))
        if i + 1 < len(positions):
            target = positions[i + 1]
            distance = math.dist(position, target)
            pieces.append(("transfer", position, target, PICK_TRANSFER[0] + PICK_TRANSFER[1] * distance))
    duration = sum(piece[3] for piece in pieces)
    samples = int(math.floor(duration * SAMPLE_RATE)) + 1
    path = []
    piece, piece_start = 0, 0.0
    for k in range(samples):
        t = k / SAMPLE_RATE
        while piece + 1 < len(pieces) and t >= piece_start + pieces[piece][3]:
            piece_start += pieces[piece][3]
            piece += 1
        kind, start, end, length = pieces[piece]
        tau = min((t - piece_start) / length, 1.0)
        if kind == "dwell":
            path.append(start)
            continue
        # Horizontal: one minimum-jerk movement. Vertical: a minimum-jerk lift to the via height
        # over the first half and a minimum-jerk descent over the second (at rest vertically at
        # the apex, so the path stays C2-smooth).
        s = minimum_jerk(tau)
        lift = minimum_jerk(2.0 * tau) if tau < 0.5 else 1.0 - minimum_jerk(2.0 * tau - 1.0)
        path.append((start[0] + (end[0] - start[0]) * s,
                     start[1] + (end[1] - start[1]) * s,
                     start[2] + (end[2] - start[2]) * s + PICK_LIFT * lift))
    return path


def sphere_curve(phase):
    """Point on the sphere at loop phase in [0, 1): a latitude wave around the equator."""
    longitude = 2.0 * math.pi * phase
    latitude = SPHERE_LATITUDE * math.sin(SPHERE_WAVES * longitude)
    cx, cy, cz = SPHERE_CENTRE
    return (cx + SPHERE_RADIUS * math.cos(latitude) * math.cos(longitude),
            cy + SPHERE_RADIUS * math.cos(latitude) * math.sin(longitude),
            cz + SPHERE_RADIUS * math.sin(latitude))


def sphere_path():
    """Clean sphere motion: power-law speed v = K * curvature^(-1/3) along the closed curve,
    SPHERE_LOOPS loops, with minimum-jerk-shaped speed ramps from and to rest."""
    fine = 20000  # curve samples per loop for arc length and curvature
    h = 1.0 / fine
    # Time per phase step at power-law speed (K = 1), periodic central differences.
    step_time = []
    for i in range(fine):
        p0, p1, p2 = sphere_curve((i - 1) * h), sphere_curve(i * h), sphere_curve((i + 1) * h)
        d1 = [(b - a) / (2 * h) for a, b in zip(p0, p2)]
        d2 = [(a - 2 * m + b) / (h * h) for a, m, b in zip(p0, p1, p2)]
        speed = math.sqrt(sum(c * c for c in d1))
        cross = (d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0])
        curvature = math.sqrt(sum(c * c for c in cross)) / speed ** 3
        step_time.append(speed * h / curvature ** (-1.0 / 3.0))
    scale = SPHERE_PERIOD / sum(step_time)
    clock = [0.0]  # power-law time at phase i*h, one loop
    for dt in step_time:
        clock.append(clock[-1] + dt * scale)
    # Real time: the power-law clock runs at rate e(t), rising from 0 to 1 over SPHERE_RAMP and
    # falling back at the end (rate = minimum-jerk profile), so the loops start and end at rest.
    travel = SPHERE_LOOPS * SPHERE_PERIOD
    duration = travel + SPHERE_RAMP  # each ramp covers half its length of power-law time
    samples = int(math.floor(duration * SAMPLE_RATE)) + 1

    def power_law_time(t):
        r = SPHERE_RAMP
        if t <= r:
            x = t / r
            return r * (2.5 * x ** 4 - 3.0 * x ** 5 + x ** 6)  # integral of minimum_jerk
        if t >= duration - r:
            return travel - power_law_time(duration - t)
        return r / 2.0 + (t - r)

    path = []
    index = 0
    for k in range(samples):
        tp = min(power_law_time(k / SAMPLE_RATE), travel)
        loop = min(int(tp // SPHERE_PERIOD), SPHERE_LOOPS - 1)
        within = tp - loop * SPHERE_PERIOD
        index = max(0, min(index, fine - 1))
        while index > 0 and clock[index] > within:
            index -= 1
        while index + 1 < fine and clock[index + 1] < within:
            index += 1
        fraction = (within - clock[index]) / (clock[index + 1] - clock[index])
        path.append(sphere_curve((index + min(max(fraction, 0.0), 1.0)) * h))
    return path


def add_noise(path, seed):
    noise = Noise(seed)
    return [tuple(c + NOISE_SIGMA * noise.normal() for c in point) for point in path]


def check_box(name, path):
    for k, point in enumerate(path):
        for axis, (c, low, high) in enumerate(zip(point, BOX_MIN, BOX_MAX)):
            if not low <= c <= high:
                raise SystemExit("%s: sample %d axis %d at %.4f m leaves the box" % (name, k, axis, c))


def write_csv(path_name, points):
    with open(path_name, "w", newline="\n") as out:
        out.write("x,y,z\n")
        for point in points:
            out.write(",".join("%.*f" % (DECIMALS, c) for c in point) + "\n")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    output = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "data")
    os.makedirs(output, exist_ok=True)
    for name, clean, seed in [("picking_synthetic.csv", picking_path(), PICK_SEED + 1),
                              ("sphere_synthetic.csv", sphere_path(), SPHERE_SEED + 1)]:
        noisy = add_noise(clean, seed)
        check_box(name, noisy)
        write_csv(os.path.join(output, name), noisy)
        print("%s: %d samples, %.2f s at %g Hz, noise sigma %.1f mm per axis" %
              (name, len(noisy), (len(noisy) - 1) / SAMPLE_RATE, SAMPLE_RATE, NOISE_SIGMA * 1000))


if __name__ == "__main__":
    main()
