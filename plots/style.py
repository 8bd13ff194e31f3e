# SPDX-License-Identifier: MIT
"""Shared matplotlib settings of the tubempm plotting scripts.

Import this module before ``matplotlib.pyplot``: it selects the non-interactive Agg backend
(the scripts only write PNG files) and sets the common rcParams (viridis, dpi 150, readable
font sizes, no LaTeX).
"""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

#: Resolution of every PNG written by the scripts.
DPI: int = 150

#: Colour map for scalar fields (equivalent plastic strain, ...).
CMAP: str = "viridis"

RC: dict[str, object] = {
    "figure.dpi": DPI,
    "savefig.dpi": DPI,
    "image.cmap": CMAP,
    "text.usetex": False,
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "legend.fontsize": 8,
    "legend.framealpha": 0.85,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "lines.linewidth": 1.4,
    "axes.formatter.useoffset": False,
}


def mark_failed(fig, failure: str, title: str = "") -> None:
    """Say in red above the plots that the run did not complete (``failure``: one line, e.g.
    from ``mpmplot.readers.run_failure``), above the figure's ``title`` if any."""
    text = failure if len(failure) <= 150 else failure[:147] + "..."
    fig.suptitle(f"{text}\n{title}" if title else text, color="red", fontsize=10,
                 fontweight="bold")


def apply() -> None:
    """Apply the shared rcParams (idempotent)."""
    matplotlib.rcParams.update(RC)


apply()


if __name__ == "__main__":
    import argparse

    _parser = argparse.ArgumentParser(
        prog="style.py",
        description="The shared matplotlib style of the tubempm plotting scripts: a module, "
        "not a plot. plot_case.py, plot_shapes.py, plot_bodies.py and the other plots/ scripts "
        "import it before matplotlib.pyplot; it selects the non-interactive Agg backend and "
        "sets the common rcParams (viridis, 150 dpi, font sizes, no LaTeX), and mark_failed() "
        "writes a run's failure in red above a figure. Run as a script it draws nothing.")
    _parser.parse_args()
    _parser.print_help()
