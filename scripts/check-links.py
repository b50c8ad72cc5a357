#!/usr/bin/env python3
"""Relative links in Markdown files: each must name an existing file, and its #anchor a heading (or an <a id>) there.

    python3 scripts/check-links.py README.md docs/cli.md ...    # exit 1, one line per broken link

Anchors are GitHub's: the heading lower-cased, every character but letters, digits, spaces, '-' and '_' dropped,
spaces turned into '-', repeated headings suffixed -1, -2, ... Headings inside fenced code blocks do not count.
Links to other sites (http:, https:, mailto:) are not followed. Standard library only.
"""
import os
import re
import sys

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
HTML_ID = re.compile(r"<a\s+(?:id|name)=\"([^\"]+)\"")


def slug(text):
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link in a heading counts by its text
    text = text.lower()
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def lines_outside_code(path):
    fenced = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if not fenced:
                yield number, line


_anchors = {}


def anchors(path):
    if path not in _anchors:
        found, seen = set(), {}
        for _, line in lines_outside_code(path):
            m = HEADING.match(line)
            if m:
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
            found.update(HTML_ID.findall(line))
        _anchors[path] = found
    return _anchors[path]


def check(path):
    errors = []
    folder = os.path.dirname(os.path.abspath(path))
    for number, line in lines_outside_code(path):
        line = re.sub(r"`[^`]*`", "", line)  # inline code is not a link
        for target in LINK.findall(line):
            if re.match(r"^[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(folder, file_part)) if file_part else os.path.abspath(path)
            if not os.path.exists(dest):
                errors.append(f"{path}:{number}: {target}: no such file")
                continue
            if anchor and dest.endswith(".md") and anchor not in anchors(dest):
                errors.append(f"{path}:{number}: {target}: no heading #{anchor} in {os.path.relpath(dest)}")
    return errors


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    errors = [e for path in argv[1:] for e in check(path)]
    for e in errors:
        print(e)
    sys.stdout.flush()
    print(f"{len(errors)} broken link(s) in {len(argv) - 1} file(s)", file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
