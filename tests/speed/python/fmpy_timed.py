"""Times the master loop of tests/interop/python/fmpy_master.py (fmpy's FMU2Slave, the
harness's Gauss-Seidel exchange, every output recorded) on a system, with a clock around
the stepping loop only: extracting, loading, instantiating and initializing are outside it,
as they are outside the harness's figure.

The exchange is fmpy_master's own (`simulate_timed`, which puts the clock around its loop).
The Rust side checks the final row against the harness's flight of the same system.

Needs tests/interop/python on PYTHONPATH. Usage: python fmpy_timed.py SYSTEM.json REPEATS
Prints one JSON object: steps, loop_seconds (one per repeat), final_bits (the last row by
column, each value as the 64 bits of its IEEE double, so the comparison is exact).
"""
import json
import struct
import sys

from fmpy_master import simulate_timed


def bits(value: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", value))[0]


def fly(system: dict) -> tuple[int, float, dict]:
    names, times, rows, loop_seconds = simulate_timed(system)
    final = {name: bits(value) for name, value in zip(names, rows[-1])}
    return len(times) - 1, loop_seconds, final


def main(system_path: str, repeats: str) -> int:
    with open(system_path) as f:
        system = json.load(f)
    loop_seconds = []
    for _ in range(int(repeats)):
        steps, seconds, final = fly(system)
        loop_seconds.append(seconds)
    print(json.dumps({"steps": steps, "loop_seconds": loop_seconds, "final_bits": final}))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
