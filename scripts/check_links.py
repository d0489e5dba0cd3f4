#!/usr/bin/env python3
"""Checks the links of the project's Markdown: README.md and docs/*.md.

Every relative link and image must name a file or folder that exists, and a link with an
#anchor into a Markdown file must name one of its headings, as GitHub makes their anchors
(lower case; letters, digits, '_', '-' and spaces kept, spaces made '-'; a repeated heading
gets -1, -2, ...). Web links (http, https, mailto) are not fetched. Links inside code blocks
and code spans are not links and are skipped.

Usage: check_links.py [ROOT]     (ROOT: the repository, default: this script's parent folder)
       check_links.py --slugs FILE.md   (print the anchors of FILE.md's headings)
Prints FILE:LINE: the broken link and why, for each, and exits 1 if there is any; 0 if none.
Standard library only.
"""
import re
import sys
import unicodedata
from pathlib import Path
from urllib.parse import unquote

# [text](target) and ![alt](target); the target ends at the first unescaped ')' or a space
# before a "title". Nested brackets in the text (one level) are allowed.
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
# [label]: target  (reference definitions)
REFERENCE_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$")
# <img src="..."> and <a href="..."> written as HTML
HTML_LINK = re.compile(r"<(?:img|a)\s[^>]*?(?:src|href)\s*=\s*\"([^\"]*)\"", re.IGNORECASE)
FENCE = re.compile(r"^\s{0,3}(```+|~~~+)")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
EXTERNAL = re.compile(r"^(?:[a-zA-Z][a-zA-Z0-9+.-]*:|//)")


def heading_text(raw):
    """The text GitHub renders for a heading's Markdown: code spans keep their content as it
    is; elsewhere links keep their text, and images, HTML tags and emphasis markers go."""
    out = []
    last = 0
    for m in CODE_SPAN.finditer(raw):
        out.append(plain_text(raw[last:m.start()]))
        out.append(m.group(2).strip())
        last = m.end()
    out.append(plain_text(raw[last:]))
    return "".join(out)


def plain_text(markdown):
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", markdown)
    text = re.sub(r"<[^>]+>", "", text)
    return re.sub(r"\*+|(?<!\w)_+|_+(?!\w)", "", text)


def slug(raw):
    """GitHub's anchor for a heading: lower case, then every character that is not a letter,
    mark, digit, connector punctuation ('_'), '-' or space dropped, and spaces made '-'."""
    out = []
    for ch in heading_text(raw).strip().lower():
        cat = unicodedata.category(ch)
        if ch in "- " or cat[0] in "LM" or cat in ("Nd", "Pc"):
            out.append(ch)
    return "".join(out).replace(" ", "-")


def lines_outside_code(text):
    """(line number, line) for each line not inside a fenced code block."""
    fence = None
    for number, line in enumerate(text.split("\n"), start=1):
        m = FENCE.match(line)
        if fence is None and m:
            fence = m.group(1)[0] * 3
            continue
        if fence is not None:
            if m and m.group(1).startswith(fence):
                fence = None
            continue
        yield number, line


def anchors(path, cache={}):
    """The set of anchors the headings of a Markdown file make (explicit <a name/id> too)."""
    if path in cache:
        return cache[path]
    seen = {}
    found = set()
    text = path.read_text(encoding="utf-8")
    for _, line in lines_outside_code(text):
        for m in re.finditer(r"<a\s[^>]*?(?:name|id)\s*=\s*\"([^\"]+)\"", line):
            found.add(m.group(1))
        m = HEADING.match(line)
        if not m:
            continue
        base = slug(m.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        found.add(base if n == 0 else f"{base}-{n}")
    cache[path] = found
    return found


def links(text):
    """(line number, target) for every link and image outside code."""
    for number, line in lines_outside_code(text):
        visible = CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line)
        for m in INLINE_LINK.finditer(visible):
            yield number, m.group(1)
        m = REFERENCE_DEF.match(visible)
        if m:
            yield number, m.group(1)
        for m in HTML_LINK.finditer(visible):
            yield number, m.group(1)


def check(path, root):
    problems = []
    text = path.read_text(encoding="utf-8")
    for number, target in links(text):
        where = f"{path.relative_to(root)}:{number}"
        if not target:
            problems.append(f"{where}: empty link")
            continue
        if EXTERNAL.match(target):
            continue  # web and mail links are not fetched
        file_part, _, anchor = target.partition("#")
        file_part = unquote(file_part)
        if file_part:
            if file_part.startswith("/"):
                resolved = (root / file_part.lstrip("/")).resolve()
            else:
                resolved = (path.parent / file_part).resolve()
            if not resolved.exists():
                shown = resolved.relative_to(root) if resolved.is_relative_to(root) else resolved
                problems.append(f"{where}: {target}: no such file or folder: {shown}")
                continue
        else:
            resolved = path.resolve()
        if anchor:
            if resolved.is_file() and resolved.suffix.lower() == ".md":
                if unquote(anchor) not in anchors(resolved):
                    problems.append(f"{where}: {target}: no heading makes the anchor #{anchor} in {resolved.name}")
            elif resolved.is_dir():
                problems.append(f"{where}: {target}: an anchor into a folder")
    return problems


def main(argv):
    if len(argv) == 3 and argv[1] == "--slugs":
        path = Path(argv[2])
        for _, line in lines_outside_code(path.read_text(encoding="utf-8")):
            m = HEADING.match(line)
            if m:
                print(f"#{slug(m.group(2))}\t{m.group(2)}")
        return 0
    root = Path(argv[1]) if len(argv) > 1 else Path(__file__).resolve().parent.parent
    root = root.resolve()
    files = [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    problems = []
    for path in files:
        if path.exists():
            problems += check(path, root)
    for p in problems:
        print(p)
    checked = sum(1 for p in files if p.exists())
    if problems:
        print(f"{len(problems)} broken link(s) in {checked} file(s)", file=sys.stderr)
        return 1
    print(f"links ok in {checked} file(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
