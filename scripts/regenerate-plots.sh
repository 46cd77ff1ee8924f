#!/usr/bin/env bash
# Regenerates committed outputs under plots/ from the shipped experiments, one thread each
# (timings are only comparable from --threads 1 runs). Counts and meshes are deterministic; the
# timing columns and the plots drawn from them depend on the machine.
#
#   bash scripts/regenerate-plots.sh            # everything: the outputs below and the study
#   bash scripts/regenerate-plots.sh quickstart compare-circle   # only these
#   bash scripts/regenerate-plots.sh study      # the study's experiments (docs/study.md)
#   SHARDS=2 bash scripts/regenerate-plots.sh study   # each experiment as 2 parts run at once,
#                                               # one thread each, then merged (docs/sharding.md)
#
# docs/performance.md records how long each took on the 2-core build machine and how much memory.
set -euo pipefail
cd "$(dirname "$0")/.."

outputs=(quickstart accuracy-vs-time compare-circle scaling chunked-tau)
study=(study-circle study-low-rough study-turning study-error-targets study-speed study-scaling accuracy-vs-time)
shards="${SHARDS:-1}"

[ $# -eq 0 ] && set -- "${outputs[@]}" study
experiments=()
for name in "$@"; do
    if [ "$name" = study ]; then
        experiments+=("${study[@]}")
    else
        experiments+=("$name")
    fi
done
# accuracy-vs-time is both an output and part of the study: run it once.
mapfile -t experiments < <(printf '%s\n' "${experiments[@]}" | awk '!seen[$0]++')

cargo build --release --locked
roamsim=./target/release/roamsim
for name in "${experiments[@]}"; do
    echo "== $name ($(date -u +%H:%M:%S))"
    if [ "$shards" -le 1 ]; then
        "$roamsim" run "experiments/$name.json" --out "plots/$name" --threads 1
        continue
    fi
    parts=()
    for k in $(seq 1 "$shards"); do
        parts+=("out/regenerate-shards/$name-$k-of-$shards")
    done
    # The parts are roamsim's own folders; a rerun replaces them.
    pids=()
    for k in $(seq 1 "$shards"); do
        "$roamsim" run "experiments/$name.json" --threads 1 --shard "$k/$shards" \
            --out "${parts[$((k - 1))]}" &
        pids+=($!)
    done
    for pid in "${pids[@]}"; do wait "$pid"; done
    "$roamsim" merge "${parts[@]}" --out "plots/$name"
done
echo "== done ($(date -u +%H:%M:%S)); now \`scripts/doc-tables\` refills the docs' figures from these outputs"
