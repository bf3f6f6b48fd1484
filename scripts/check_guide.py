#!/usr/bin/env python3
"""Checks the built guide (docs/guide): every page of SUMMARY.md was rendered, every page is
in SUMMARY.md and tested (included by crates/vitro-guide/src/lib.rs), and every relative link
and image of every page points at a file that exists.

Usage: python3 scripts/check_guide.py docs/guide   (after `mdbook build docs/guide`)
"""

import pathlib
import re
import sys


def main() -> int:
    guide = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "docs/guide")
    src, book = guide / "src", guide / "book"
    root = guide.parent.parent
    lib = (root / "crates/vitro-guide/src/lib.rs").read_text()
    summary = (src / "SUMMARY.md").read_text()
    listed = re.findall(r"\]\(([^)]+\.md)\)", summary)
    problems = []
    pages = sorted(p.name for p in src.glob("*.md") if p.name != "SUMMARY.md")
    for page in pages:
        if page not in listed:
            problems.append(f"{page} is not in SUMMARY.md")
        if f'docs/guide/src/{page}"' not in lib:
            problems.append(f"{page} is not included in crates/vitro-guide/src/lib.rs (untested)")
    for page in listed:
        if not (book / page.replace(".md", ".html")).is_file():
            problems.append(f"{page} was not rendered to {book}")
        text = (src / page).read_text()
        # Links and images outside code blocks.
        prose = re.sub(r"```.*?```", "", text, flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", prose):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue
            path = target.split("#")[0]
            if not (src / path).exists():
                problems.append(f"{page}: broken link {target}")
    for p in problems:
        print(f"guide: {p}")
    if not problems:
        print(f"guide: {len(listed)} pages rendered, all tested, links and images resolve")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
