"""A figure of the report (:class:`ReportFigure`) and its rendering to PNG, on several
processes where asked (:func:`render_pngs`)."""

import io
import multiprocessing
import signal
from dataclasses import dataclass

from matplotlib.backends.backend_agg import FigureCanvasAgg

__all__ = ["ReportFigure", "render_pngs"]


@dataclass
class ReportFigure:
    """One figure of the report.

    Attributes
    ----------
    name : str
        File stem of the PNG (``results/plots/<name>.png``).
    title : str
        Heading of the figure in the report.
    caption : str
        What the figure shows, for a reader who has not seen the paper.
    figure : matplotlib.figure.Figure
    claims : tuple of str
        Ids of the claims it illustrates: the report shows it in the section of the
        first of them (empty: in the closing "Figures" section).
    alternate : ReportFigure or None
        Another view of the same thing (the Cornell box with its element mesh drawn),
        shown at a toggle below the figure in the HTML report (``<details>``) and after
        it in the Markdown report; its title is the toggle's label.
    """

    name: str
    title: str
    caption: str
    figure: object
    claims: tuple = ()
    alternate: object = None

    def png(self):
        """The figure as PNG bytes (100 dpi)."""
        # The canvas's own print_png draws once, running the layout engine inside the
        # draw; savefig() first draws without rendering to run it, then again. The bytes
        # are the same (checked on every figure of the report), the CPU time a sixth less.
        buf = io.BytesIO()
        self.figure.set_dpi(100)
        FigureCanvasAgg(self.figure).print_png(buf)
        return buf.getvalue()


# The figures a forked renderer reads (set by render_pngs before it forks).
_TO_RENDER = ()


def _render(k):
    return _TO_RENDER[k].png()


def render_pngs(figures, jobs=1, advance=None):
    """The PNG bytes of every figure, rendered on up to `jobs` processes.

    Rendering dominates the report's time (about half a second per figure), and each
    figure renders alone, so forked processes share the work; they inherit the figures
    and send back only the bytes, identical to a serial rendering.

    Parameters
    ----------
    figures : sequence of ReportFigure
    jobs : int
        Processes to use; 1, or a platform without ``fork``, renders here, in order.
    advance : callable, optional
        Called with no argument as each figure is rendered, in order (a progress line:
        :meth:`hrbench_analysis.stages.Stage.advance`).

    Returns
    -------
    pngs : list of bytes
        In the order of `figures`.
    """
    global _TO_RENDER
    advance = advance or (lambda: None)
    if jobs <= 1 or len(figures) < 2 or "fork" not in multiprocessing.get_all_start_methods():
        return [_advanced(f.png(), advance) for f in figures]
    _TO_RENDER = tuple(figures)
    try:
        with multiprocessing.get_context("fork").Pool(min(jobs, len(figures)),
                                                      initializer=_worker_signals) as pool:
            return [_advanced(png, advance)
                    for png in pool.imap(_render, range(len(figures)), chunksize=1)]
    finally:
        _TO_RENDER = ()


def _advanced(png, advance):
    # The PNG, once `advance` has counted it.
    advance()
    return png


def _worker_signals():
    # A forked worker inherits the command's handlers, which end engine runs and raise
    # an interrupt: the pool ends its workers with SIGTERM, and Ctrl-C is the parent's.
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
