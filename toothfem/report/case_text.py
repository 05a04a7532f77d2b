"""What a case file says beyond its values, for report.html: the keys it sets (declared,
as against toothfem's defaults), each key's comment and each section's, and the ASSUMPTION
marker of a reasoned choice where no source fixes a value."""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

#: The marker of a reasoned choice where no source fixes a value (case files, schema).
ASSUMPTION = "ASSUMPTION"


@dataclass
class Comment:
    """A comment of the case file: its first line and its text (continuations joined)."""
    line: int                 # 1-based line of the case file
    text: str


@dataclass
class CaseText:
    """What the case file says beyond its values: the keys it sets (dotted, with the index
    of an array of tables: ``measured[0].efficiency``), each key's comment and each
    section's (the file's head under ``""``)."""
    declared: set
    keys: dict                # key -> Comment
    sections: dict            # section -> Comment
    path: str


_HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\-]+)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=\s*(.*)$")


def _split_comment(value: str):
    """(value, comment or None) of the text after ``key =``: the first ``#`` outside a
    quoted string."""
    quoting, i = None, 0
    while i < len(value):
        ch = value[i]
        if quoting:
            if ch == "\\" and quoting == '"':
                i += 1                      # an escaped character of a basic string
            elif ch == quoting:
                quoting = None
        elif ch in "\"'":
            quoting = ch
        elif ch == "#":
            return value[:i].rstrip(), value[i + 1:].strip()
        i += 1
    return value.rstrip(), None


def read_case_text(path) -> CaseText:
    """The keys a case file sets and its comments.

    A comment on a key's line is that key's; a comment on a section's line, or a comment
    line before the section's first key, is the section's; a comment line indented after a
    commented line continues that comment; any other comment line is a note of its section.

    Parameters
    ----------
    path : str or pathlib.Path
        The case file (TOML, UTF-8).

    Returns
    -------
    CaseText
    """
    path = Path(path)
    text = path.read_text(encoding="utf-8", errors="replace")
    declared: set[str] = set()
    keys: dict[str, Comment] = {}
    sections: dict[str, Comment] = {}
    counts: dict[str, int] = {}
    section, last = "", None

    def extend(comment: Comment, more: str) -> Comment:
        comment.text = f"{comment.text} {more}".strip()
        return comment

    for n, raw in enumerate(text.splitlines(), start=1):
        stripped = raw.strip()
        if not stripped:
            last = None
            continue
        if stripped.startswith("#"):
            body = stripped.lstrip("#").strip()
            if last is not None and raw[:1].isspace():      # an indented continuation
                extend(last, body)
            else:                                           # a note of the section
                last = extend(sections.setdefault(section, Comment(n, "")), body)
            continue
        head = _HEADER.match(raw)
        if head:
            section = head.group(2)
            if head.group(1) == "[[":                       # an array of tables
                counts[section] = counts.get(section, -1) + 1
                section = f"{section}[{counts[section]}]"
            last = extend(sections.setdefault(section, Comment(n, "")),
                          (head.group(3) or "").lstrip("#").strip())
            continue
        key = _KEY.match(raw)
        if key:
            dotted = f"{section or 'case'}.{key.group(1)}"
            declared.add(dotted)
            _, comment = _split_comment(key.group(2))
            last = None
            if comment:
                last = keys[dotted] = Comment(n, comment)
    return CaseText(declared, keys, sections, str(path))


def reason(text: str) -> str:
    """A comment's text if it says more than the ASSUMPTION marker.

    Parameters
    ----------
    text : str
        A comment or a schema text that says ASSUMPTION.

    Returns
    -------
    str
        ``text``, or '' when the marker is all it says.
    """
    return text if re.sub(rf"{ASSUMPTION}S?", "", text).strip(" :;,.-()") else ""
