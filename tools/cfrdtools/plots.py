"""matplotlib without a display (Agg), and the figures' common steps."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401 - the scripts take plt from here


def save(fig, path, dpi=120, rect=None, close=False):
    """Lay the figure out (in `rect` of the page) and write it; returns the figure."""
    fig.tight_layout(**({"rect": rect} if rect else {}))
    fig.savefig(path, dpi=dpi)
    if close:
        plt.close(fig)
    return fig


def note(fig, text):
    """A grey note under the figure; the rect for save() that leaves room for it."""
    if text:
        fig.text(0.5, 0.01, text, ha="center", fontsize=8, color="0.25")
    return (0, 0.04 if text else 0, 1, 1)
