#!/usr/bin/env python3
"""Checks the documentation's relative links (README.md, docs/**/*.md, bench/results/**/README.md).

Usage: check_links.py REPOSITORY_ROOT

Every Markdown link or image target `[x](path)` / `![x](path)` that is not a web address (http:, https:),
a mail address (mailto:) or an anchor in the same page (#...) must name a file or folder that exists, relative
to the page that holds it (`path#anchor` is checked as `path`). Links inside code spans and fenced code blocks
are not links and are skipped. README.md must stay within 300 lines.

Prints every broken link as FILE:LINE: broken link 'target' and exits 1; exits 1 too when README.md is longer
than 300 lines; otherwise prints "N links checked, all resolve" and exits 0. Exit 2 on a bad argument.
"""
import os
import re
import sys

README_MAX_LINES = 300

# [text](target) or ![alt](target), with an optional "title"; the text may hold one level of brackets.
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
CODE_SPAN = re.compile(r"(`+).*?\1")
FENCE = re.compile(r"^\s{0,3}(`{3,}|~{3,})")
SKIP = ("http:", "https:", "mailto:", "#")


def pages(root):
    """The Markdown files to check, as paths relative to root, in a stable order."""
    found = []
    if os.path.isfile(os.path.join(root, "README.md")):
        found.append("README.md")
    for top, want in (("docs", lambda name: name.endswith(".md")),
                      (os.path.join("bench", "results"), lambda name: name == "README.md")):
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames.sort()
            for name in sorted(filenames):
                if want(name):
                    found.append(os.path.relpath(os.path.join(dirpath, name), root))
    return found


def links(text):
    """(line number, target) of every link outside code, in order."""
    fence = None
    for number, line in enumerate(text.split("\n"), start=1):
        m = FENCE.match(line)
        if m:
            marker = m.group(1)
            if fence is None:
                fence = marker
            elif marker[0] == fence[0] and len(marker) >= len(fence):
                fence = None
            continue
        if fence is not None:
            continue
        for link in LINK.finditer(CODE_SPAN.sub("", line)):
            yield number, link.group(1)


def main(argv):
    if len(argv) != 2:
        print("usage: check_links.py REPOSITORY_ROOT", file=sys.stderr)
        return 2
    root = argv[1]
    if not os.path.isdir(root):
        print(f"check_links.py: '{root}' is not a directory", file=sys.stderr)
        return 2
    readme = os.path.join(root, "README.md")
    if not os.path.isfile(readme):
        print(f"check_links.py: '{root}' has no README.md (give the repository root)", file=sys.stderr)
        return 2

    failed = False
    with open(readme, encoding="utf-8") as f:
        readme_lines = len(f.read().splitlines())
    if readme_lines > README_MAX_LINES:
        print(f"README.md: {readme_lines} lines, more than the {README_MAX_LINES} allowed")
        failed = True

    checked = 0
    for page in pages(root):
        with open(os.path.join(root, page), encoding="utf-8") as f:
            text = f.read()
        base = os.path.dirname(os.path.join(root, page))
        for number, target in links(text):
            if target.startswith(SKIP):
                continue
            path = target.split("#", 1)[0]
            checked += 1
            if not path or not os.path.exists(os.path.normpath(os.path.join(base, path))):
                print(f"{page}:{number}: broken link '{target}'")
                failed = True
    if failed:
        return 1
    print(f"{checked} links checked, all resolve")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
