"""The picture of the core's layers on docs/architecture.rst, drawn from the code's own imports.

At each build grimp (import-linter's graph) reads every import of ``windpump``; the imports between
its sub-packages and top-level modules are drawn as a ladder, each one on the row above the
highest it imports, with the imports no shorter path already implies (the transitive reduction).
The picture is therefore what the code does, not what a page says it does.
"""

from __future__ import annotations

import functools
import html
from pathlib import Path

ROW, BOX_W, BOX_H, WIDTH = 78, 128, 34, 760
MARGIN = 70  # each side: the lanes of the lines that skip rows
LEFT_OUT = {"_old_paths"}  # the old paths' finder: imports by name, outside the ladder


def part(module: str) -> str | None:
    """``windpump.model.design`` -> ``model``; the package's own ``__init__`` -> None."""
    pieces = module.split(".")
    return pieces[1] if len(pieces) > 1 and pieces[1] not in LEFT_OUT else None


def layer_edges() -> set[tuple[str, str]]:
    """(importer, imported) between the core's sub-packages and top-level modules."""
    import grimp

    graph = grimp.build_graph("windpump")
    edges = set()
    for module in graph.modules:
        for imported in graph.find_modules_directly_imported_by(module):
            a, b = part(module), part(imported)
            if a and b and a != b:
                edges.add((a, b))
    return edges


def reduced(edges: set[tuple[str, str]]) -> set[tuple[str, str]]:
    """The edges no longer path implies (an import circle would make every level undefined)."""

    def reaches(a: str, b: str, skip: tuple[str, str]) -> bool:
        seen, todo = set(), [a]
        while todo:
            for x, y in edges:
                if x == todo[-1] and (x, y) != skip and y not in seen:
                    if y == b:
                        return True
                    seen.add(y)
                    todo.insert(0, y)
            todo.pop()
        return False

    return {(a, b) for a, b in edges if not reaches(a, b, (a, b))}


def levels(edges: set[tuple[str, str]]) -> dict[str, int]:
    """0 for what imports nothing of the core, else one above the highest it imports."""
    nodes = {n for edge in edges for n in edge}

    @functools.cache
    def level(node: str) -> int:
        below = [b for a, b in edges if a == node]
        return 1 + max(map(level, below)) if below else 0

    return {node: level(node) for node in nodes}


def mean_neighbour(edges: set[tuple[str, str]], place: dict[str, float], node: str) -> float:
    """The mean place (0 left, 1 right) of what ``node`` imports and what imports it."""
    near = [place[b] for a, b in edges if a == node] + [place[a] for a, b in edges if b == node]
    return sum(near) / len(near) if near else 0.5


def ordered_rows(edges: set[tuple[str, str]]) -> list[list[str]]:
    """The nodes by level, top row first, each row ordered by its neighbours' mean place (a few
    sweeps of the barycentre rule) so that few lines cross."""
    rank = levels(edges)
    rows = [
        sorted(n for n, r in rank.items() if r == level)
        for level in range(max(rank.values()), -1, -1)
    ]
    for _ in range(4):
        for row in rows:
            place = {n: i / max(len(r) - 1, 1) for r in rows for i, n in enumerate(r)}
            row.sort(key=functools.partial(mean_neighbour, edges, place))
    return rows


def svg(edges: set[tuple[str, str]]) -> str:
    """An SVG of the ladder: a row per level, the top of the ladder first; a line that skips rows
    bows out to the side rather than cross the boxes between."""
    rows = ordered_rows(edges)
    where = {}
    for y, row in enumerate(rows):
        for x, node in enumerate(row):
            where[node] = (MARGIN + (x + 0.5) * (WIDTH - 2 * MARGIN) / len(row), 10 + y * ROW)
    height = 20 + (len(rows) - 1) * ROW + BOX_H
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {WIDTH} {height}" '
        f'width="{WIDTH}" height="{height}" role="img" font-family="monospace" font-size="13">',
        "<title>The core's layers: each box imports only boxes on lower rows</title>",
        '<defs><marker id="head" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" '
        'markerHeight="7" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="#555"/></marker></defs>',
    ]
    for a, b in sorted(reduced(edges)):
        (xa, ya), (xb, yb) = where[a], where[b]
        ya += BOX_H
        if yb - ya > ROW:  # skips a row: down the nearer side's lane, dashed
            lane = 12 if (xa + xb) / 2 < WIDTH / 2 else WIDTH - 12
            path = (
                f"M{xa:.0f},{ya:.0f} Q{lane},{ya:.0f} {lane},{(ya + yb) / 2:.0f} "
                f"Q{lane},{yb:.0f} {xb:.0f},{yb:.0f}"
            )
            dash = ' stroke-dasharray="5,3"'
        else:
            dash = ""
            path = f"M{xa:.0f},{ya:.0f} L{xb:.0f},{yb:.0f}"
        out.append(f'<path d="{path}" fill="none" stroke="#555"{dash} marker-end="url(#head)"/>')
    for node, (x, y) in sorted(where.items()):
        out.append(
            f'<rect x="{x - BOX_W / 2:.0f}" y="{y:.0f}" width="{BOX_W}" height="{BOX_H}" rx="5" '
            'fill="#eef3f8" stroke="#1f4e79"/>'
            f'<text x="{x:.0f}" y="{y + BOX_H / 2 + 4:.0f}" text-anchor="middle" fill="#111">'
            f"{html.escape(node)}</text>"
        )
    out.append("</svg>")
    return "\n".join(out)


def write_picture(app) -> None:
    target = Path(app.srcdir) / "_generated" / "layers.svg"
    target.parent.mkdir(exist_ok=True)
    target.write_text(svg(layer_edges()), encoding="utf-8")


def setup(app):
    app.connect("builder-inited", write_picture)
    return {"parallel_read_safe": True, "version": "1"}
