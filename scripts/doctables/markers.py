"""Finding, checking and filling the generated text of a doc.

A marked span opens with `<!-- scripts/doc-tables NAME ARGUMENTS -->` (the arguments as a shell
would split them) and closes with `<!-- /scripts/doc-tables -->`. When the opening marker ends
its line the span is a block: the text between the markers is whole lines. Otherwise it is
inline: one figure inside a sentence, on the marker's line. Spans do not nest. A marker
written inside inline code (right after a backtick, as the docs do when they describe the
markers) is text, not a marker.
"""

import re
import shlex
from dataclasses import dataclass

OPEN = re.compile(r"(?<!`)<!-- scripts/doc-tables (.+?) -->")
CLOSE_TEXT = "<!-- /scripts/doc-tables -->"
CLOSE = re.compile(r"(?<!`)" + re.escape(CLOSE_TEXT))


class MarkerError(Exception):
    """A marker that cannot be read: unclosed, nested, or an inline span across lines."""


@dataclass
class Span:
    line: int  # 1-based line of the opening marker
    command: str  # what follows `scripts/doc-tables` in the opening marker
    name: str
    arguments: list
    block: bool
    start: int  # offset of the generated text
    end: int  # offset of the closing marker


def spans(text, where):
    """Every marked span of `text`, in order; `where` names the doc in errors."""
    found = []
    position = 0
    while True:
        opening = OPEN.search(text, position)
        if opening is None:
            break
        line = text.count("\n", 0, opening.start()) + 1
        command = opening.group(1)
        try:
            words = shlex.split(command)
        except ValueError as error:
            raise MarkerError(f"{where}:{line}: cannot split {command!r}: {error}")
        if not words:
            raise MarkerError(f"{where}:{line}: a marker with no generator name")
        block = text.startswith("\n", opening.end())
        start = opening.end() + (1 if block else 0)
        closing = CLOSE.search(text, start)
        if closing is None:
            raise MarkerError(f"{where}:{line}: `{command}` is never closed by `{CLOSE_TEXT}`")
        end = closing.start()
        inner_open = OPEN.search(text, start, end)
        if inner_open is not None:
            inner_line = text.count("\n", 0, inner_open.start()) + 1
            raise MarkerError(f"{where}:{inner_line}: a marker inside the span of `{command}` "
                              f"(line {line}): close the first one before opening another")
        if block and end > 0 and text[end - 1] != "\n":
            raise MarkerError(f"{where}:{line}: block `{command}`: the closing marker must start "
                              "its own line")
        if not block and "\n" in text[start:end]:
            raise MarkerError(f"{where}:{line}: inline `{command}`: its closing marker must be on "
                              "the same line")
        found.append(Span(line, command, words[0], words[1:], block, start, end))
        position = closing.end()
    return found


def expected_text(span, printed):
    """The text a span must hold, given what its generator printed."""
    if span.block:
        return printed if printed.endswith("\n") or not printed else printed + "\n"
    if "\n" in printed.rstrip("\n"):
        raise MarkerError(f"line {span.line}: inline `{span.command}` printed several lines: "
                          "use a block")
    return printed.rstrip("\n")


def fill(text, replacements):
    """`text` with each span's generated text replaced: `replacements` is [(span, new text)]."""
    pieces = []
    position = 0
    for span, new in replacements:
        pieces.append(text[position:span.start])
        pieces.append(new)
        position = span.end
    pieces.append(text[position:])
    return "".join(pieces)
