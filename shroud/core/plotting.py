"""Figures in the paper's style: labelled axes with units, off-screen PNG."""

from __future__ import annotations

from pathlib import Path

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


def save(fig, path: Path, top: float = 1.0) -> Path:
    """Lay out and write ``fig``; ``top`` < 1 keeps the strip above it free (a legend for every panel)."""
    fig.tight_layout(rect=(0.0, 0.0, 1.0, top))
    fig.savefig(path)
    _pyplot().close(fig)
    return path
