#!/usr/bin/env bash
# Regenerates every committed output under plots/ from the shipped experiments, one thread each
# (timings are only comparable from --threads 1 runs). Counts and meshes are deterministic; the
# timing columns and the plots drawn from them depend on the machine.
#
#   bash scripts/regenerate-plots.sh            # all of them (9 min 50 s on 2026-12-02; scaling needs about 9 GiB)
#   bash scripts/regenerate-plots.sh quickstart compare-circle   # only these
set -euo pipefail
cd "$(dirname "$0")/.."

experiments=("$@")
if [ ${#experiments[@]} -eq 0 ]; then
    experiments=(quickstart accuracy-vs-time compare-circle scaling chunked-tau)
fi

cargo build --release --locked
for name in "${experiments[@]}"; do
    echo "== $name"
    ./target/release/roamsim run "experiments/$name.json" --out "plots/$name" --threads 1
done
