#!/usr/bin/env bash
# Regenerates committed outputs under plots/ from the shipped experiments, one thread each
# (timings are only comparable from --threads 1 runs). Counts and meshes are deterministic; the
# timing columns and the plots drawn from them depend on the machine.
#
#   bash scripts/regenerate-plots.sh            # everything: the outputs below, the study and
#                                               # the reproductions
#   bash scripts/regenerate-plots.sh quickstart compare-circle   # only these
#   bash scripts/regenerate-plots.sh study      # the study's experiments (docs/study.md)
#   bash scripts/regenerate-plots.sh reproductions   # every experiment docs/reproductions/
#                                               # quotes (vanek-16k: about 4 GB of memory)
#   SHARDS=2 bash scripts/regenerate-plots.sh study   # each experiment as 2 parts run at once,
#                                               # one thread each, then merged (docs/sharding.md)
#
# docs/performance.md records how long each took on the 2-core build machine and how much memory.
set -euo pipefail
cd "$(dirname "$0")/.."

outputs=(quickstart accuracy-vs-time compare-circle scaling chunked-tau)
study=(study-circle study-low-rough study-turning study-error-targets study-speed study-scaling accuracy-vs-time)
# The experiments docs/reproductions/*.md quote (chunked-tau is also an output above).
reproductions=(wu-table1 roam-pop roam-pop-circle roam-deferral lindstrom-tau-sweep rottger-fans
    stitching-strips-peak stitching-strips-circle vanek-circle vanek-16k chunked-tau lauritsen
    lauritsen-65537)
shards="${SHARDS:-1}"

[ $# -eq 0 ] && set -- "${outputs[@]}" study reproductions
experiments=()
for name in "$@"; do
    case "$name" in
        study) experiments+=("${study[@]}") ;;
        reproductions) experiments+=("${reproductions[@]}") ;;
        *) experiments+=("$name") ;;
    esac
done
# An experiment named by two groups (accuracy-vs-time, chunked-tau) runs once.
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
