"""Figures in the paper's style: labelled axes with units, off-screen PNG."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from shroud.base.log import warn
from shroud.base.outputs import replacing

STYLE = {
    "figure.dpi": 110, "savefig.dpi": 150, "font.size": 9, "axes.grid": True,
    "grid.alpha": 0.3, "axes.titlesize": 9, "legend.fontsize": 8, "lines.linewidth": 1.2,
}
# One colour per model in every figure, so the four-model comparisons read alike.
MODEL_COLOURS = {"reduced": "tab:red", "full": "tab:blue", "fe-reduced": "tab:green",
                 "fe": "black", "paper": "tab:gray", "extended": "tab:purple",
                 "shell": "tab:brown", "shell-reduced": "tab:orange"}


def _pyplot():
    """matplotlib.pyplot on the off-screen Agg backend, imported when a figure is drawn (0.7 s)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def figure(nrows: int = 1, ncols: int = 1, width: float = 6.4, height: float | None = None):
    plt = _pyplot()
    plt.rcParams.update(STYLE)
    height = height if height is not None else 2.6 * nrows + 0.6
    return plt.subplots(nrows, ncols, figsize=(width, height), squeeze=False)


def plain_log(ax, which: str = "y") -> None:
    """A log scale on ``ax``'s ``which`` ("x" or "y") axis labelled in plain numbers: an axis spanning less than
    a decade has no power-of-ten tick, and matplotlib's default then labels its minor ticks as "4 x 10^0"."""
    from matplotlib.ticker import LogFormatter

    class MinorLogFormatter(LogFormatter):
        """Over one to two decades matplotlib labels the minor ticks 2, 3, 4, 6 of each: on an x axis 3 and
        4 collide in a narrow panel; 2 and 5 alone keep the labels apart (a y axis stacks them: all kept)."""

        def set_locs(self, locs=None):
            super().set_locs(locs)
            if self._sublabels is not None and 1 < len(self._sublabels) < 10:
                self._sublabels = {1, 2, 5}

    getattr(ax, f"set_{which}scale")("log")
    axis = getattr(ax, f"{which}axis")
    axis.set_major_formatter(LogFormatter())
    axis.set_minor_formatter((MinorLogFormatter if which == "x" else LogFormatter)(labelOnlyBase=False,
                                                                                  minor_thresholds=(2, 0.5)))


def save(fig, path: Path, top: float = 1.0) -> Path:
    """Lay out and write ``fig``; ``top`` < 1 keeps the strip above it free (a legend for every panel).

    A legend entry whose curve another one covers wholly (hidden_entries) is a warning: the figure
    says something the reader cannot see.
    """
    fig.tight_layout(rect=(0.0, 0.0, 1.0, top))
    with replacing(Path(path)) as tmp:
        fig.savefig(tmp)
    for entry in hidden_entries(fig):
        warn(f"{Path(path).name}: {entry}; draw it dashed above, or offset it, and say so in the caption")
    _pyplot().close(fig)
    return path


def hidden_entries(fig, sample: int = 400) -> list[str]:
    """Legend entries of ``fig`` drawn invisibly: every point of the curve lies under solid curves drawn
    above it (later, or at a higher zorder) that are at least as wide, within half a pixel.

    A dashed curve drawn above a solid one leaves it visible in its gaps; a solid one above covers it.
    Call on a drawn figure (after savefig: the transforms are final).
    """
    found = []
    for ax in fig.axes:
        lines = [l for l in ax.get_lines() if l.get_visible() and len(l.get_xydata())]
        order = sorted(range(len(lines)), key=lambda i: (lines[i].get_zorder(), i))
        for rank, i in enumerate(order):
            below = lines[i]
            label = below.get_label()
            if label.startswith("_") or below.get_linestyle() in ("None", " ", ""):
                continue
            px = fig.dpi / 72.0
            covers = [lines[j] for j in order[rank + 1:]
                      if lines[j].get_linestyle() == "-" and lines[j].get_linewidth() >= below.get_linewidth()]
            if not covers:
                continue
            points = ax.transData.transform(below.get_xydata())
            points = points[np.linspace(0, len(points) - 1, min(sample, len(points))).astype(int)]
            near = np.full(len(points), np.inf)
            for line in covers:
                near = np.minimum(near, _distance_to_polyline(points, ax.transData.transform(line.get_xydata())))
            slack = max(0.5, 0.5 * px * (max(l.get_linewidth() for l in covers) - below.get_linewidth()))
            if np.all(near <= slack):
                found.append(f"{ax.get_title() or 'a panel'}: '{label}' is hidden under another curve")
    return found


def _distance_to_polyline(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Distance of each of ``points`` (n, 2) to the polyline through ``vertices`` (m, 2), same units."""
    if len(vertices) == 1:
        return np.linalg.norm(points - vertices[0], axis=1)
    a, b = vertices[:-1], vertices[1:]
    ab = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    s = np.clip(np.einsum("nij,ij->ni", points[:, None, :] - a[None], ab) / length2, 0.0, 1.0)
    closest = a[None] + s[..., None] * ab[None]
    return np.min(np.linalg.norm(points[:, None, :] - closest, axis=2), axis=1)
