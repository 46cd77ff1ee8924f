#!/usr/bin/env bash
# The out-of-core demonstration of issue #33 (docs/reproductions/lauritsen.md, "A source read
# from disk"): a terrain file of more than 8 GB flown by chunked LOD under a 1 GB memory limit,
# its heights read from disk on demand.
#
#   scripts/demo-out-of-core.sh [DATA_DIR]      # DATA_DIR defaults to out/; 20.4 GB free needed
#
# 1. Makes DATA_DIR/terrain-65537.raw if absent: 65 537² i16le samples (8.6 GB) tiled and
#    mirrored from the shipped SRTM tile by scripts/make-large-terrain.py (streams: a few rows).
# 2. Prepares DATA_DIR/terrain-65537.pyr from it if absent: `roamsim prepare`, 65² chunks,
#    30 m posts (11.8 GB), under `ulimit -v` 1 GiB, with `/usr/bin/time -v` (wall time, peak RSS).
# 3. Links out/terrain-65537.pyr to it when DATA_DIR is not out/ (the experiment names
#    ../../out/terrain-65537.pyr), then runs experiments/out-of-core/lauritsen-pyramid.json under
#    the same 1 GiB limit (`systemd-run --scope -p MemoryMax=1G` when it works, else
#    `ulimit -v`), with `/usr/bin/time -v`, into out/lauritsen-pyramid/, and prints the peak
#    resident set and the summary of frames.csv's read columns (chunks_read, read_latency_*_us,
#    read_wait_us) and summary.json's read facts.
#
# Needs: a release build (`cargo build --release`, done here if missing), python3, GNU time.
# Never overwrites a file it did not make: the raw and the pyramid are made only when absent,
# and the link only when out/terrain-65537.pyr does not exist.
set -euo pipefail
cd "$(dirname "$0")/.."

DATA_DIR=${1:-out}
SIDE=65537
RAW="$DATA_DIR/terrain-$SIDE.raw"
PYRAMID="$DATA_DIR/terrain-$SIDE.pyr"
LINK="out/terrain-$SIDE.pyr"
EXPERIMENT=experiments/out-of-core/lauritsen-pyramid.json
LIMIT_KIB=1048576 # 1 GiB
ROAMSIM=target/release/roamsim

mkdir -p "$DATA_DIR" out
# Refuse early when the disk cannot take what is still to be made (8.6 GB raw, 11.8 GB pyramid).
NEED=0
[ -e "$PYRAMID" ] || NEED=$((NEED + 11830000000))
[ -e "$PYRAMID" ] || [ -e "$RAW" ] || NEED=$((NEED + 8590196738))
FREE=$(df --output=avail -B1 "$DATA_DIR" | tail -1)
if [ "$FREE" -lt "$NEED" ]; then
    echo "$DATA_DIR: $FREE bytes free; making the files needs $NEED" >&2
    exit 1
fi
[ -x "$ROAMSIM" ] || cargo build --release --locked

if [ ! -e "$RAW" ]; then
    echo "== making $RAW (8.6 GB)"
    python3 scripts/make-large-terrain.py --side "$SIDE" --out "$RAW"
fi

if [ ! -e "$PYRAMID" ]; then
    echo "== preparing $PYRAMID under ulimit -v $LIMIT_KIB KiB"
    (ulimit -v "$LIMIT_KIB"; /usr/bin/time -v "$ROAMSIM" prepare "$RAW" --raw-side "$SIDE" \
        --raw-sample i16le --spacing-m 30 --chunk-level 6 --out "$PYRAMID") \
        2> >(tee "$DATA_DIR/prepare-time.txt" | grep -E "Elapsed|Maximum resident|prepare: .*100%" >&2)
fi

if [ "$(realpath -m "$PYRAMID")" != "$(realpath -m "$LINK")" ] && [ ! -e "$LINK" ]; then
    ln -s "$(realpath "$PYRAMID")" "$LINK"
fi

RUN=("$ROAMSIM" run "$EXPERIMENT" --out out/lauritsen-pyramid)
echo "== flying $EXPERIMENT under a 1 GiB limit"
if systemd-run --user --scope --quiet -p MemoryMax=1G true 2>/dev/null; then
    systemd-run --user --scope --quiet -p MemoryMax=1G -p MemorySwapMax=0 \
        /usr/bin/time -v "${RUN[@]}" 2> out/lauritsen-pyramid-time.txt
else
    (ulimit -v "$LIMIT_KIB"; /usr/bin/time -v "${RUN[@]}") 2> out/lauritsen-pyramid-time.txt
fi
grep -E "Elapsed|Maximum resident" out/lauritsen-pyramid-time.txt

python3 - out/lauritsen-pyramid <<'EOF'
import csv, json, os, sys
folder = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(folder, "frames.csv"))))
for column in ["chunks_read", "read_latency_max_us", "read_latency_mean_us", "read_wait_us"]:
    values = sorted(float(r[column]) for r in rows if r.get(column))
    if not values:
        sys.exit(f"{folder}/frames.csv: no {column} column")
    pick = lambda p: values[max(1, -(-len(values) * p // 100)) - 1]
    print(f"{column}: sum {sum(values):.0f}, p50 {pick(50):.0f}, p95 {pick(95):.0f}, "
          f"max {values[-1]:.0f} over {len(values)} frames")
summary = json.load(open(os.path.join(folder, "summary.json")))
for entry in summary["algorithms"]:
    facts = {k: v for k, v in entry["facts"].items() if k.startswith(("read_", "chunks_read"))}
    print(entry.get("label", entry.get("name")), facts)
print("run.peak_resident_bytes:", summary["run"]["peak_resident_bytes"])
EOF
