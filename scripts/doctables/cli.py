"""The command line of `scripts/doc-tables`: fill the docs, check them, print one generator."""

import argparse
import difflib
import os
import sys
from pathlib import Path

from .generators import GENERATORS, UnknownGenerator, render
from .markers import MarkerError, expected_text, fill, spans
from .outputs import ROOT, OutputMissing

USAGE = """\
scripts/doc-tables                 fill every doc's generated text from the committed outputs
scripts/doc-tables --check         fail (exit 1), naming doc, line and command, where a doc's
                                   generated text differs from what the outputs print
scripts/doc-tables --doc FILE ...  only these docs (with or without --check)
scripts/doc-tables --print NAME [ARGUMENTS ...]   print one generator's text
scripts/doc-tables --list          every generator"""


def default_docs():
    docs = [ROOT / "README.md", ROOT / "ARCHITECTURE.md"]
    docs += sorted((ROOT / "docs").glob("*.md"))
    docs += sorted((ROOT / "docs" / "reproductions").glob("*.md"))
    return [doc for doc in docs if doc.exists()]


def shown(path):
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def generated(doc):
    """(text, [(span, expected text)], [problems]) for one doc."""
    text = doc.read_text(encoding="utf-8")
    problems = []
    replacements = []
    try:
        found = spans(text, shown(doc))
    except MarkerError as error:
        return text, [], [str(error)]
    for span in found:
        try:
            printed = render(span.name, span.arguments)
            replacements.append((span, expected_text(span, printed)))
        except (OutputMissing, UnknownGenerator, MarkerError) as error:
            problems.append(f"{shown(doc)}:{span.line}: `scripts/doc-tables {span.command}`: "
                            f"{error}")
    return text, replacements, problems


def differences(doc, text, replacements):
    """One message per span whose text differs from what its generator prints."""
    messages = []
    for span, new in replacements:
        old = text[span.start:span.end]
        if old == new:
            continue
        if span.block:
            diff = difflib.unified_diff(old.splitlines(), new.splitlines(), "in the doc",
                                        "printed from the outputs", lineterm="", n=0)
            detail = "\n".join(list(diff)[:24])
        else:
            detail = f"  in the doc: {old!r}\n  printed from the outputs: {new!r}"
        messages.append(f"{shown(doc)}:{span.line}: `scripts/doc-tables {span.command}` differs "
                        f"from what it prints from the committed outputs:\n{detail}")
    return messages


def write_whole(path, text):
    """Writes `text` to `path` whole or not at all (a temporary file renamed over it)."""
    temporary = path.with_name(f".{path.name}.doc-tables-tmp")
    temporary.write_text(text, encoding="utf-8")
    os.replace(temporary, path)


def main(argv):
    parser = argparse.ArgumentParser(prog="scripts/doc-tables", usage=USAGE, add_help=True)
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--doc", action="append", type=Path, default=[])
    parser.add_argument("--print", dest="print_name", metavar="NAME")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("arguments", nargs="*")
    options = parser.parse_args(argv)

    if options.list:
        for name, (_function, description) in GENERATORS.items():
            print(f"{name:22} {description}")
        return 0
    if options.print_name:
        try:
            sys.stdout.write(render(options.print_name, options.arguments))
        except (OutputMissing, UnknownGenerator) as error:
            print(f"scripts/doc-tables: {error}", file=sys.stderr)
            return 1
        return 0
    if options.arguments:
        parser.error(f"unexpected arguments {options.arguments} (generator arguments go after "
                     "--print NAME)")

    docs = options.doc or default_docs()
    problems = []
    results = []
    for doc in docs:
        if not doc.exists():
            problems.append(f"{doc}: no such doc")
            continue
        text, replacements, doc_problems = generated(doc)
        problems += doc_problems
        results.append((doc, text, replacements))
    n_spans = sum(len(replacements) for _doc, _text, replacements in results)

    if options.check:
        for doc, text, replacements in results:
            problems += differences(doc, text, replacements)
        for problem in problems:
            print(problem, file=sys.stderr)
        if problems:
            print(f"scripts/doc-tables --check: {len(problems)} problem(s) in {len(docs)} doc(s); "
                  "`scripts/doc-tables` refills the generated text from the committed outputs",
                  file=sys.stderr)
            return 1
        print(f"scripts/doc-tables --check: {n_spans} generated span(s) in {len(docs)} doc(s) "
              "match the committed outputs")
        return 0

    if problems:
        for problem in problems:
            print(problem, file=sys.stderr)
        print("scripts/doc-tables: nothing written", file=sys.stderr)
        return 1
    for doc, text, replacements in results:
        new = fill(text, replacements)
        if new != text:
            write_whole(doc, new)
            print(f"filled {shown(doc)}")
    return 0
