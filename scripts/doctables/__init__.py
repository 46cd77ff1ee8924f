"""The figures of roamsim's docs, printed from the committed outputs (`scripts/doc-tables`).

A doc holds generated text between two markers; the opening one names the command that prints
it, so a reader can run it:

    <!-- scripts/doc-tables study-circle -->
    | entry | ... |            (a block: the marker ends its line, the text is whole lines)
    <!-- /scripts/doc-tables -->

    ... the reference at <!-- scripts/doc-tables cell compare-circle "reference τ=3.3" rendered -->6216<!-- /scripts/doc-tables --> ...
                               (inline: a figure inside a sentence)

Everything printed is read from a run's own outputs under plots/ (report.md tables,
summary.json records): the scripts select, join and order figures, and compute a figure only
where the doc says how (a ratio of two printed figures). Python 3 standard library only.

`ROAMSIM_PLOTS=DIR` reads the outputs from DIR instead of plots/ (laid out the same way, one
folder per experiment), to see what a generator prints from a fresh run before it is committed:

    roamsim run experiments/study-turning.json --out /tmp/runs/study-turning --threads 1
    ROAMSIM_PLOTS=/tmp/runs scripts/doc-tables --print study-turning

Modules: `outputs` reads the committed outputs' report.md tables; `runs` reads one run's
summary.json statistics and facts and frames.csv rows; `markers` finds and fills the marked
text; `generators` holds every generator by name, the reproduction pages' in `reproductions`,
which gathers `repro_common`'s shared readers and the pages' own modules (`repro_rottger`,
`repro_lauritsen`, `repro_wu`, `repro_vanek`), the study's time axis and inline figures (figure,
ratio, more, less, growth) in `study`; `cli` is the command line.
"""
