#!/usr/bin/env python3
"""Checks the book built from docs/ (docs/book.md).

usage: check_book.py DOCS_DIR BUILD_DIR

- every page of DOCS_DIR (a .md file other than SUMMARY.md) is in SUMMARY.md;
- every relative link and image of every built page leads to a file of the book, and a
  link to an anchor (`page.html#part`) to an element with that id. Links with a scheme
  (https:, mailto:) or to another host are skipped: they cannot be checked offline.

Prints each problem with its page, and exits 1 if there is any.
"""

import re
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

# mdBook's pages that repeat or index the others: print.html holds every page again with
# its links rewritten, toc.html is the sidebar, 404.html links from the site's root.
GENERATED = {"print.html", "toc.html", "404.html"}


class Page(HTMLParser):
    """The ids and the link targets (href, src) of one HTML page."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids = set()
        self.links = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if value is None:
                continue
            if name == "id":
                self.ids.add(value)
            elif name in ("href", "src") and tag in ("a", "img", "source", "embed", "object"):
                self.links.append(value)


def read(path):
    page = Page()
    page.feed(path.read_text(encoding="utf-8"))
    return page


def summary_problems(docs):
    summary = (docs / "SUMMARY.md").read_text(encoding="utf-8")
    listed = {Path(m) for m in re.findall(r"\]\(([^)#\s]+\.md)\)", summary)}
    pages = {p.relative_to(docs) for p in docs.rglob("*.md") if p.name != "SUMMARY.md"}
    problems = [f"SUMMARY.md: the page {p} is not listed" for p in sorted(pages - listed)]
    problems += [f"SUMMARY.md: lists {p}, which does not exist" for p in sorted(listed - pages)]
    return problems


def link_problems(build):
    pages = {p: read(p) for p in build.rglob("*.html")}
    problems = []
    for path, page in sorted(pages.items()):
        if path.name in GENERATED:
            continue
        for link in page.links:
            parts = urlsplit(link)
            if parts.scheme or parts.netloc:
                continue
            target = path if parts.path == "" else (path.parent / unquote(parts.path))
            if parts.path.endswith("/"):
                target = target / "index.html"
            target = target.resolve()
            where = path.relative_to(build)
            if not target.is_file():
                problems.append(f"{where}: broken link {link} (no file {target})")
                continue
            if parts.fragment and target.suffix == ".html":
                ids = pages[target].ids if target in pages else read(target).ids
                if unquote(parts.fragment) not in ids:
                    problems.append(f"{where}: broken link {link} (no anchor #{parts.fragment})")
    return problems, len(pages)


def main():
    docs, build = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()
    problems = summary_problems(docs)
    more, count = link_problems(build)
    problems += more
    for problem in problems:
        print(problem)
    print(f"book: {count} pages checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
