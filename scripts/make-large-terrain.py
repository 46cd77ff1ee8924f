#!/usr/bin/env python3
"""Makes a large 16-bit raw terrain from the shipped SRTM tile, for `roamsim prepare` and the
on-demand demonstration of docs/reproductions/lauritsen.md ("A source read from disk").

The tile (experiments/data/N48E009.hgt, 1201² big-endian i16, north row first) is tiled and
mirrored (every other copy reflected, so the terrain is continuous across copies) to SIDE × SIDE
samples, written row by row as little-endian i16, north row first: `--raw-sample i16le`. Voids
(-32768) are filled with the previous valid sample of the tile, row by row. It streams: memory is
a few rows whatever SIDE is.

    scripts/make-large-terrain.py --side 65537 --out /big/disk/terrain-65537.raw   # 8.6 GB
    scripts/make-large-terrain.py --side 16385 --out scratch/terrain-16385.raw     # 537 MB

It refuses to overwrite an existing file.
"""

import argparse
import array
import os
import sys

TILE = os.path.join(os.path.dirname(__file__), "..", "experiments", "data", "N48E009.hgt")
TILE_SIDE = 1201


def tile_rows():
    """The tile's rows, north first, as little-endian i16 arrays with voids filled."""
    data = open(TILE, "rb").read()
    if len(data) != TILE_SIDE * TILE_SIDE * 2:
        sys.exit(f"{TILE}: expected {TILE_SIDE * TILE_SIDE * 2} bytes, found {len(data)}")
    samples = array.array("h", data)
    if sys.byteorder == "little":
        samples.byteswap()  # The file is big-endian.
    last = next(z for z in samples if z != -32768)
    for k, z in enumerate(samples):
        if z == -32768:
            samples[k] = last
        else:
            last = z
    return [samples[r * TILE_SIDE:(r + 1) * TILE_SIDE] for r in range(TILE_SIDE)]


def mirrored(index, period):
    """Index into 0..=period of position `index` on a line of mirrored copies."""
    t = index % (2 * period)
    return t if t <= period else 2 * period - t


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=65537, help="samples per side (2^n + 1)")
    parser.add_argument("--out", required=True, help="the raw file to write")
    args = parser.parse_args()
    side = args.side
    if side < 3 or (side - 1) & (side - 2) != 0:
        sys.exit(f"--side {side}: expected 2^n + 1 samples")
    if os.path.exists(args.out):
        sys.exit(f"{args.out}: exists; roamsim's scripts do not overwrite files")
    rows = tile_rows()
    period = TILE_SIDE - 1
    patterns = {}
    partial = f"{args.out}.partial-{os.getpid()}"
    with open(partial, "wb") as out:
        for r in range(side):
            source = mirrored(r, period)
            if source not in patterns:
                row = rows[source]
                # One mirrored period (2·1200 samples), repeated to the side.
                cycle = (row[:period] + row[period:0:-1]).tobytes()
                repeat = side // (2 * period) + 1
                patterns = {source: (cycle * repeat)[: 2 * side]}
            out.write(patterns[source])
            if r % 4096 == 0:
                print(f"make-large-terrain: row {r}/{side}", file=sys.stderr)
    os.rename(partial, args.out)
    print(f"{args.out}: {side} × {side} i16le samples, north row first, "
          f"{2 * side * side} bytes")


if __name__ == "__main__":
    main()
