"""The page's Content-Security-Policy: a second wall behind ``escape.as_text``, so that markup
which ever reached a pane still could not run.

A served page is Bokeh's HTML: its scripts come from the server (``static/``) but for two inline
ones, the set-up and the one that opens the session with its token, which differs each time. So
each HTML response gets a fresh nonce, written into its own ``<script>`` tags, and the policy
lets the browser run only the server's files and scripts carrying that nonce. A ``<script>``
that Panel's HTML pane re-creates from a message, an ``onerror=`` or ``onload=`` attribute, or a
``javascript:`` URL carries none and is blocked.

What the policy allows, and why:

- ``script-src 'self' 'nonce-…' 'unsafe-eval'``: Bokeh compiles a ``CustomJS`` callback's code
  with ``new Function`` (the page's keyboard, upload and viewport scripts are such callbacks).
- ``style-src 'self' 'unsafe-inline'``: Bokeh and Panel style every component with inline styles
  and style sheets written at run time.
- ``img-src 'self' data: blob:``, ``font-src 'self' data:``: Bokeh draws icons and saves
  figures as data and blob URLs.
- ``connect-src 'self'``: the page's websocket and its uploads (``upload_route``) go to its own
  server only.
- ``object-src 'none'``, ``base-uri 'self'``, ``form-action 'self'``, ``frame-src 'none'``.

No ``frame-ancestors``: a course page may embed the explorer in an iframe.
"""

from __future__ import annotations

import re
import secrets

from tornado.httputil import HTTPHeaders
from tornado.web import OutputTransform

POLICY = (
    "default-src 'self'",
    "script-src 'self' 'nonce-{nonce}' 'unsafe-eval'",
    "style-src 'self' 'unsafe-inline'",
    "img-src 'self' data: blob:",
    "font-src 'self' data:",
    "connect-src 'self'",
    "object-src 'none'",
    "base-uri 'self'",
    "form-action 'self'",
    "frame-src 'none'",
)
# The opening of a <script> tag the page's own HTML writes (Bokeh's template), not one that has a
# nonce already.
SCRIPT_TAG = re.compile(rb"<script(?![^>]*\bnonce=)(?=[\s>])", re.IGNORECASE)


def content_security_policy(nonce: str) -> str:
    """The policy of one page, whose own inline scripts carry ``nonce``.

    >>> content_security_policy("abc").split("; ")[1]
    "script-src 'self' 'nonce-abc' 'unsafe-eval'"
    """
    return "; ".join(POLICY).format(nonce=nonce)


class ScriptNonce(OutputTransform):
    """A Tornado output transform: an HTML response gets a fresh nonce in its ``<script>`` tags
    and the policy that runs those alone (``content_security_policy``); other responses pass as
    they are. It runs before the compression (``hooks.compress_responses``)."""

    def __init__(self, request) -> None:
        self.nonce: bytes | None = None

    def transform_first_chunk(
        self, status_code: int, headers: HTTPHeaders, chunk: bytes, finishing: bool
    ) -> tuple[int, HTTPHeaders, bytes]:
        html = headers.get("Content-Type", "").startswith("text/html")
        # a body whose length was declared before it was all written cannot be rewritten
        if html and (finishing or "Content-Length" not in headers):
            nonce = secrets.token_urlsafe(18)
            self.nonce = nonce.encode()
            headers["Content-Security-Policy"] = content_security_policy(nonce)
            chunk = self.transform_chunk(chunk, finishing)
            if "Content-Length" in headers:
                headers["Content-Length"] = str(len(chunk))
        return status_code, headers, chunk

    def transform_chunk(self, chunk: bytes, finishing: bool) -> bytes:
        if self.nonce is None:
            return chunk
        return SCRIPT_TAG.sub(b'<script nonce="' + self.nonce + b'"', chunk)


def protect_pages(server) -> None:
    """Give every HTML page of the Bokeh ``server`` (a Tornado application) its policy."""
    if ScriptNonce not in server.transforms:
        server.transforms.insert(0, ScriptNonce)
