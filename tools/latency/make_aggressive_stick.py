#!/usr/bin/env python3
"""Writes config/flights/eval_stick_aggressive.rec: a synthesised stick recording of full
deflections for fieldcast-latency's stick flight. A generic 8-bit joystick (X roll, Y pitch,
Rz rudder, Z throttle) reporting at 100 Hz; each slam of the stick takes 40 ms end to end.

    python3 tools/latency/make_aggressive_stick.py > config/flights/eval_stick_aggressive.rec
"""

RATE_HZ = 100
RAMP_S = 0.04
T0_NS = 1_000_000_000  # recordings carry CLOCK_MONOTONIC times; any origin will do

X, Y, RZ, Z = 0x00010030, 0x00010031, 0x00010035, 0x00010032
CENTRE = 128

# (start s, X, Y, Rz): the stick is slammed to each position at its start time and held
PHASES = [
    (0.0, 128, 128, 128),  # straight and level
    (0.6, 255, 128, 128),  # full right roll
    (1.2, 128, 255, 128),  # full pull
    (1.5, 0, 128, 128),    # full left roll
    (2.5, 128, 0, 255),    # full push with right rudder
    (3.0, 255, 128, 128),  # full right roll
    (3.4, 0, 255, 128),    # left roll while pulling
    (4.2, 128, 128, 0),    # centred, left rudder
    (4.6, 128, 128, 128),  # hands off
]
END_S = 6.0


def target(t):
    """The commanded (x, y, rz) at time t, ramping linearly over RAMP_S after each change."""
    previous = PHASES[0][1:]
    for i, (start, *position) in enumerate(PHASES):
        if t < start:
            break
        before = PHASES[i - 1][1:] if i > 0 else position
        f = min(1.0, (t - start) / RAMP_S) if i > 0 else 1.0
        previous = [round(b + f * (p - b)) for b, p in zip(before, position)]
    return previous


def main():
    print("fieldcast-input 1")
    print("# Synthesised by tools/latency/make_aggressive_stick.py: full deflections of roll, pitch and")
    print("# rudder, slammed in 40 ms, 100 reports a second; fieldcast-latency's stick flight.")
    print("device usb 1209 0001 Synthetic full-deflection stick")
    for usage in (X, Y, RZ, Z):
        print(f"control {usage:08x} axis 0 255")
    last = None
    for k in range(int(END_S * RATE_HZ) + 1):
        t_ns = T0_NS + k * 1_000_000_000 // RATE_HZ
        x, y, rz = target(k / RATE_HZ)
        values = {X: x, Y: y, RZ: rz, Z: CENTRE}
        changed = [u for u in (X, Y, RZ, Z) if last is None or last[u] != values[u]]
        for u in changed:
            print(f"v {t_ns} {u:08x} {values[u]}")
        print(f"s {t_ns}")
        last = values


if __name__ == "__main__":
    main()
