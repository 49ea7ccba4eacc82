"""Where blurlab's documentation is, for the pages blurlab writes: the study report links to it.

The site has no hosted copy, so a link goes, in order, to:

1. ``$BLURLAB_DOCS_URL`` + ``PAGE.html``, when that variable is set: wherever the site that
   ``make docs`` builds is served or copied (a folder given as a ``file:`` URL works too);
2. the built site of the source checkout blurlab runs from (``site/PAGE.html``, after
   ``make docs``), as a ``file:`` URL;
3. that checkout's Markdown page (``docs/PAGE.md``), as a ``file:`` URL.

An installed wheel carries no docs: there ``docs_url`` returns None unless the variable is set.
"""

from __future__ import annotations

import html
import os
import re
from pathlib import Path

DOCS_URL_VARIABLE = "BLURLAB_DOCS_URL"

# The repository root when blurlab runs from a source checkout (python/blurlab/ inside it).
_CHECKOUT = Path(__file__).resolve().parents[2]


def docs_url(page: str) -> str | None:
    """The address of a docs page by its name (``"study"`` for docs/study.md), or None where
    there is none to link to (an installed wheel, with BLURLAB_DOCS_URL unset)."""
    if not re.fullmatch(r"[a-z0-9_]+", page):
        raise ValueError(f"docs page names are lower-case words like 'study', not {page!r}")
    base = os.environ.get(DOCS_URL_VARIABLE)
    if base:
        return base.rstrip("/") + f"/{page}.html"
    source = _CHECKOUT / "docs" / f"{page}.md"
    if not (_CHECKOUT / "mkdocs.yml").is_file():
        return None
    if not source.is_file():
        raise ValueError(f"no docs page {page!r}: {source} does not exist")
    built = _CHECKOUT / "site" / f"{page}.html"
    return (built if built.is_file() else source).as_uri()


def docs_anchor(page: str, text: str) -> str:
    """HTML for a link to docs page `page` reading `text`; where there is nothing to link to (an
    installed wheel, BLURLAB_DOCS_URL unset) the text with the page's source path instead, so a
    report written anywhere still says where to read."""
    url = docs_url(page)
    if url is None:
        return f"{html.escape(text)} (docs/{page}.md in blurlab's source)"
    return f"<a href='{html.escape(url)}'>{html.escape(text)}</a>"
