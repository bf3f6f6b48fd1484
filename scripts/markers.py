"""Generated blocks in Markdown files: the text between two HTML comments,

    <!-- TOOL: NAME -->
    ...
    <!-- /TOOL: NAME -->

written by the script TOOL (benchmarks.py, doc_tables.py) and left alone by everything else.
Standard library only; shared by the scripts that write such blocks."""

import re


class MarkerError(Exception):
    """A block's markers are missing, unpaired or repeated."""


def markers(tool, name):
    """The begin and end comment of block NAME written by TOOL."""
    return f"<!-- {tool}: {name} -->", f"<!-- /{tool}: {name} -->"


def replace(doc, tool, name, body, where="the document"):
    """`doc` with block NAME's text replaced by `body` (a list of lines, markers excluded)."""
    begin, end = markers(tool, name)
    pattern = re.compile(re.escape(begin) + r".*?" + re.escape(end), re.S)
    found = len(pattern.findall(doc))
    if found != 1:
        raise MarkerError(
            f"{where} has {'no' if found == 0 else found} blocks `{name}` ({begin} ... {end})"
        )
    text = "\n".join([begin, *body, end])
    return pattern.sub(lambda _: text, doc, count=1)


def body(doc, tool, name):
    """The lines between block NAME's markers (None if it has none)."""
    begin, end = markers(tool, name)
    m = re.search(re.escape(begin) + r"\n?(.*?)\n?" + re.escape(end), doc, re.S)
    return m[1].split("\n") if m else None


def names(doc, tool, where="the document"):
    """The names of TOOL's blocks in `doc`, in order; every begin marker must have its end."""
    begins = re.findall(rf"<!-- {re.escape(tool)}: (\S+) -->", doc)
    ends = re.findall(rf"<!-- /{re.escape(tool)}: (\S+) -->", doc)
    if sorted(begins) != sorted(ends):
        raise MarkerError(f"{where}: unpaired {tool} markers (begin {begins}, end {ends})")
    repeated = sorted({n for n in begins if begins.count(n) > 1})
    if repeated:
        raise MarkerError(f"{where}: {tool} blocks repeated: {', '.join(repeated)}")
    return begins
