"""Text from outside the page shown as text: what a link, a file (its name, cells, header and
station fields) or a message that echoes either says is never run, nor read as markup.

Every such text reaches a pane through ``as_text``: the page's notices and messages are Markdown
and HTML panes, and Panel's HTML pane runs a ``<script>`` it is given. Each character that HTML
or Markdown reads as markup becomes its numeric character reference, which both render as the
character itself: ``<img onerror=…>`` shows as typed, ``**`` stays two stars, and a line break
cannot start a Markdown block.
"""

from __future__ import annotations

import re

# HTML's markup in an element or a double-quoted attribute (& < > "), Markdown's inline markup
# (emphasis, code, links, images, tables, escapes), an e-mail autolink's '@', and line breaks: no
# block can start inside a message.
MARKUP = '&<>"`*_~[]#|\\@\n\r'
# C0, DEL and C1, and Unicode's bidirectional formatting characters (the Arabic letter mark,
# left-to-right and right-to-left marks, embeddings, overrides, isolates): one of those in an
# echoed value reordered the rest of its line on screen (U+202E showed the notice backwards).
CONTROLS = (*range(0x20), *range(0x7F, 0xA0), 0x61C, 0x200E, 0x200F, *range(0x202A, 0x202F))
CONTROLS += tuple(range(0x2066, 0x206A))
_REFERENCES = str.maketrans(
    {character: f"&#{ord(character)};" for character in MARKUP}
    # other controls show as the replacement character, as a browser shows a NUL
    | {code: "\ufffd" for code in CONTROLS if chr(code) not in MARKUP + "\t"}
)
# A dot before a letter would make a bare domain a link (lab.csv, www.example.org), and a colon
# before a slash a URL (http://); a decimal point, and a colon in a sentence, stay as they are.
# A list's marker, or an indent (a code block), is read only at the start.
_LINK_PUNCTUATION = re.compile(r"\.(?=[^\W\d_])|:(?=/)")
_BLOCK_START = re.compile(r"^(?:\s+|[+-](?=\s|$)|\d+[.)](?=\s|$))")
_END_BLANKS = re.compile(r"\s+$")  # a paragraph's are trimmed: shown as typed


def as_text(raw: object) -> str:
    """``raw`` (a link's key or value, a file's name or cell, a message that echoes one) as text
    for a Markdown or HTML pane (an element's content or a double-quoted attribute): every
    character that either reads as markup written as its numeric character reference, which
    both show as the character itself. Letters, digits, spaces, a number's sign and decimal
    point pass as they are; other control characters, and the bidirectional formatting
    characters, become U+FFFD.

    Examples
    --------
    >>> as_text("3.1")
    '3.1'
    >>> as_text('<img src=x onerror="run()">')
    '&#60;img src=x onerror=&#34;run()&#34;&#62;'
    >>> as_text("'abc' at http://x")
    "'abc' at http&#58;//x"
    >>> as_text("- 1. not a list")
    '&#45; 1. not a list'
    >>> as_text("**h** at lab.csv")
    '&#42;&#42;h&#42;&#42; at lab&#46;csv'
    """
    text = _LINK_PUNCTUATION.sub(_references, str(raw).translate(_REFERENCES))
    text = _END_BLANKS.sub(_references, text, count=1)
    return _BLOCK_START.sub(_start_as_text, text, count=1)


def _references(found: re.Match) -> str:
    """The characters found, as numeric character references."""
    return "".join(f"&#{ord(character)};" for character in found.group())


def _start_as_text(found: re.Match) -> str:
    """A text's leading blanks, or its list marker's last character, as references."""
    start = found.group()
    cut = 0 if start[0].isspace() else len(start) - 1
    return start[:cut] + "".join(f"&#{ord(character)};" for character in start[cut:])
