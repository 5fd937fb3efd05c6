#!/usr/bin/env python3
"""Checks the documentation's links: every relative link and image exists, and every
`#anchor` names a heading (or an `id`) of its page.

Two passes, standard library only:

- The built book (`docs/book/**/*.html`, from `mdbook build docs`): every relative `href`
  and `src` resolves to a file, and every fragment to an `id` of the page it names. A link
  that leaves the book resolves against the repository, as it does when the book is opened
  from the checkout (`docs/book/` lies where `docs/src/` does).
- The Markdown sources read on their own (on a forge, in an editor): the book's pages under
  `docs/src/`, and README.md, ARCHITECTURE.md, CHANGELOG.md and every other `*.md` of the
  repository outside `target/` and build output. Every relative link and image resolves to
  a file or folder, and a fragment into a Markdown file to one of its headings, with the
  ids a forge gives them (lower case, punctuation dropped, spaces to hyphens).

Usage: python3 docs/check_links.py [--sources-only]
Exit status 0 when every link resolves, 1 otherwise (each broken link on a line).
"""

from __future__ import annotations

import html.parser
import os
import re
import sys
import unicodedata
from pathlib import Path
from urllib.parse import unquote, urlsplit

ROOT = Path(__file__).resolve().parent.parent
BOOK = ROOT / "docs" / "book"
SKIP_DIRS = {".git", "target", "node_modules", "book", "py-venv", ".pytest_cache"}
# mdbook's own pages whose links are relative to the site's root, not to the page.
SKIP_HTML = {"404.html", "print.html", "toc.html"}


def is_external(target: str) -> bool:
    return bool(urlsplit(target).scheme) or target.startswith("//")


# ---------------------------------------------------------------------------------------
# The built book


class _Links(html.parser.HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.links: list[tuple[int, str]] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if value is None:
                continue
            if name in ("id", "name"):
                self.ids.add(value)
            elif name in ("href", "src") and tag != "link" and tag != "script":
                self.links.append((self.getpos()[0], value))


_html_cache: dict[Path, _Links] = {}


def parse_html(path: Path) -> _Links:
    if path not in _html_cache:
        parser = _Links()
        parser.feed(path.read_text(encoding="utf-8"))
        _html_cache[path] = parser
    return _html_cache[path]


def check_book() -> list[str]:
    errors = []
    pages = sorted(p for p in BOOK.rglob("*.html") if p.name not in SKIP_HTML)
    if not pages:
        return [f"{BOOK.relative_to(ROOT)}: no pages; run `mdbook build docs` first"]
    for page in pages:
        for line, target in parse_html(page).links:
            if is_external(target) or target.startswith("mailto:"):
                continue
            parts = urlsplit(target)
            path = unquote(parts.path)
            where = f"{page.relative_to(ROOT)}:{line}: {target}"
            dest = page if path == "" else (page.parent / path).resolve()
            if not dest.exists():
                errors.append(f"{where}: no such file")
                continue
            if parts.fragment and dest.is_file() and dest.suffix == ".html":
                if unquote(parts.fragment) not in parse_html(dest).ids:
                    errors.append(f"{where}: no id `{parts.fragment}` in {dest.name}")
    return errors


# ---------------------------------------------------------------------------------------
# The Markdown sources

FENCE = re.compile(r"^\s*(```|~~~)")
INLINE_CODE = re.compile(r"(`+)(.+?)\1")
# [text](target "title") and ![alt](target); the text may hold one level of brackets.
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
HTML_ID = re.compile(r"""\b(?:id|name)\s*=\s*["']([^"']+)["']""")


def strip_code(line: str) -> str:
    return INLINE_CODE.sub(lambda m: " " * len(m.group(0)), line)


def heading_text(raw: str) -> str:
    """A heading's text as rendered: code spans' contents kept, link targets, emphasis
    markers and HTML tags dropped."""
    text = INLINE_CODE.sub(lambda m: m.group(2).strip(), raw)
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"<[^>]+>", "", text)
    return text.replace("*", "").replace("\\", "")


def slug(text: str) -> str:
    """The id a forge (and mdbook) gives a heading: lower case, letters, digits, `-` and
    `_` kept, whitespace to `-`, everything else dropped."""
    out = []
    for ch in heading_text(text).strip().lower():
        if ch.isspace():
            out.append("-")
        elif ch in "-_" or unicodedata.category(ch)[0] in "LNM":
            out.append(ch)
    return "".join(out)


def markdown_lines(path: Path) -> list[tuple[int, str]]:
    """The lines outside fenced code blocks, numbered from 1."""
    lines, fenced = [], False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            lines.append((number, line))
    return lines


_anchor_cache: dict[Path, set[str]] = {}


def markdown_anchors(path: Path) -> set[str]:
    if path not in _anchor_cache:
        anchors: set[str] = set()
        seen: dict[str, int] = {}
        for _, line in markdown_lines(path):
            m = HEADING.match(line)
            if m:
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                anchors.add(base if n == 0 else f"{base}-{n}")
            anchors.update(HTML_ID.findall(line))
        _anchor_cache[path] = anchors
    return _anchor_cache[path]


def markdown_files() -> list[Path]:
    files = []
    for dirpath, dirnames, filenames in os.walk(ROOT):
        dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS)
        files.extend(Path(dirpath) / f for f in sorted(filenames) if f.endswith(".md"))
    return files


def check_markdown(path: Path) -> list[str]:
    errors = []
    for number, line in markdown_lines(path):
        text = strip_code(line)
        targets = [m.group(1) for m in INLINE_LINK.finditer(text)]
        m = REFERENCE_DEF.match(text)
        if m:
            targets.append(m.group(1))
        for target in targets:
            if is_external(target) or target.startswith("mailto:"):
                continue
            parts = urlsplit(target)
            where = f"{path.relative_to(ROOT)}:{number}: {target}"
            dest = path if parts.path == "" else (path.parent / unquote(parts.path))
            if not dest.exists():
                errors.append(f"{where}: no such file")
                continue
            if parts.fragment and dest.is_file() and dest.suffix == ".md":
                if unquote(parts.fragment) not in markdown_anchors(dest.resolve()):
                    errors.append(f"{where}: no heading `{parts.fragment}` in {dest.name}")
    return errors


def main() -> int:
    sources_only = "--sources-only" in sys.argv[1:]
    errors = []
    files = markdown_files()
    for path in files:
        errors.extend(check_markdown(path))
    checked = f"{len(files)} Markdown files"
    if not sources_only:
        errors.extend(check_book())
        checked += f" and {len(list(BOOK.rglob('*.html')))} pages of the built book"
    for error in errors:
        print(error)
    print(f"links: {checked} checked, {len(errors)} broken", file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
