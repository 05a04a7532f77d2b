"""The Markdown a command wrote (report.md) as report.html's sections, and the folder's
pictures as data: URIs (the page fetches nothing)."""
from __future__ import annotations

import base64
import re
from pathlib import Path

#: A PNG file's first eight bytes (the PNG specification, Sec. 5.2): a figure is embedded
#: only if it is one.
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_uri(path: Path) -> str | None:
    """A PNG file as a data: URI (the page embeds every picture).

    Parameters
    ----------
    path : pathlib.Path
        The file.

    Returns
    -------
    str or None
        None if it cannot be read or is not a PNG (:data:`PNG_SIGNATURE`).
    """
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if not data.startswith(PNG_SIGNATURE):
        return None
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def markdown_sections(text: str, folder: Path, embedded: set) -> list:
    """The sections of a Markdown report as HTML: each ``## `` section, the part before the
    first one under "Overview" (its ``# `` title left out: the page's header says it); a
    ``## Warnings`` section is left out (the page's own lists every warning). Pictures are
    embedded (their paths added to ``embedded``); links outside the folder lose their
    target (the address stays as text).

    Parameters
    ----------
    text : str
        The report's Markdown (CommonMark with tables; raw HTML is shown as text).
    folder : pathlib.Path
        The folder its pictures are in.
    embedded : set
        Adds the folder-relative path of every picture embedded.

    Returns
    -------
    list of (str, str)
        (title, html) of each section.
    """
    from markdown_it import MarkdownIt

    md = MarkdownIt("commonmark", {"html": False}).enable("table")
    parts: list[tuple[str, list[str]]] = []
    lines: list[str] = []
    title = "Overview"
    for line in text.splitlines():
        if line.startswith("## "):
            parts.append((title, lines))
            title, lines = line[3:].strip(), []
        elif line.startswith("# ") and title == "Overview" and not any(x.strip() for x in lines):
            continue
        else:
            lines.append(line)
    parts.append((title, lines))
    out = []
    for title, lines in parts:
        body = "\n".join(lines).strip()
        if not body or title.lower() == "warnings":
            continue
        tokens = md.parse(body)
        for tok in tokens:
            for _i, child in enumerate(tok.children or ()):
                if child.type == "image":
                    _embed_image(child, folder, embedded)
                elif child.type == "link_open":
                    href = str(child.attrGet("href") or "")
                    if re.match(r"^[a-z][a-z0-9+.-]*:|^//", href, re.I):
                        child.attrs.pop("href", None)
                        child.attrSet("title", href)
        out.append((title, md.renderer.render(tokens, md.options, {})))
    return out


def _embed_image(tok, folder: Path, embedded: set) -> None:
    """An image token's source as a data: URI of the folder's PNG, or its alt text shown
    as missing (never a broken picture)."""
    src = tok.attrGet("src") or ""
    path = (folder / src).resolve()
    uri = None
    if folder.resolve() in path.parents and path.suffix.lower() == ".png":
        uri = png_uri(path)
    if uri is None:
        tok.type, tok.tag = "text", ""
        tok.content = f"[figure {src} is not in the folder]"
        tok.children = None
        return
    tok.attrSet("src", uri)
    embedded.add(path.relative_to(folder.resolve()).as_posix())
