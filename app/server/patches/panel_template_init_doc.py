"""A template's page reference forgotten with its session
(``panel.template.base.BaseTemplate._init_doc``).

Made for panel 1.9.4 (applied on panel 1.9 only): it wraps ``BaseTemplate._init_doc(self,
doc=None, comm=None, title=None, notebook=False, location=True)`` and reads ``state._fake_roots``
and the template's ``_refs``; ``tests/app/test_app_patches.py`` fails when those change shape.
"""

from __future__ import annotations


def fake_roots_forgotten() -> None:
    """Panel (1.9) lists the reference of every page's template root in ``state._fake_roots``
    (``BaseTemplate._init_doc``) and means to drop it when the page's session is destroyed
    (``BaseTemplate._server_destroy`` pops it from the template's ``_refs``), but never records
    it in ``_refs``: each page served left its string there for good (30 after a hall of 30),
    each one made among that page's objects and keeping its memory once the page was gone
    (docs/known-issues.rst), and every change of every component scans the list. Here the
    references a template's page adds are recorded in its ``_refs``, which Panel then drops."""
    import panel
    from panel.io.state import state
    from panel.template.base import BaseTemplate

    init_doc = BaseTemplate._init_doc
    if getattr(init_doc, "forgets", False) or not panel.__version__.startswith("1.9."):
        return

    def _init_doc(self, doc=None, *args, **kwargs):
        before = set(state._fake_roots)
        document = init_doc(self, doc, *args, **kwargs)
        added = [ref for ref in state._fake_roots if ref not in before]
        if len(added) == 1 and document not in self._refs:
            self._refs[document] = added[0]
        return document

    _init_doc.forgets = True  # type: ignore[attr-defined]
    _init_doc.panel = init_doc  # type: ignore[attr-defined]
    BaseTemplate._init_doc = _init_doc  # type: ignore[method-assign]
