"""Hierarchy statistics: the quantities of Garmann & Müller's lemmas, measured from links.

The proof that ``L = Theta(N / eps)`` for two parallel plates (oracle
``max(A_i, A_j) / r <= eps``) rests on three lemmas about the stored hierarchy: the leaves
near the closest approach have size ``Theta(eps d)``; an element of size ``A`` links
partners at centre distances between ``r_min`` and ``r_max``, which cover a stretch of
length ``D`` on the other plate with ``r_max - r_min <= D <= r_max + r_min``, so
``D = Theta(A / eps)``; and so every element has ``Theta(1 / eps)`` partners. This
module measures these quantities on the link list of one refinement (``hrbench links``)
and reduces them to a few numbers per run, the *hierarchy statistics*
(:data:`STATISTICS`), which claim formulas may read like counters. The definitions are
in ``docs/lemmas.md``.

How a sweep uses them (:mod:`hrbench_analysis.sweep`): a claim whose ``x`` or ``y`` reads a
statistic (:func:`claim_statistics`) runs each point as usual (``hrbench run ...
--count-only --json``) and then :func:`measure`: the scene's patches
(``hrbench save``), the link list into a temporary file (``hrbench links``, deleted
afterwards), the statistics, which the results cache keeps beside the run's record
(:func:`stored_statistics`; the record stays what the engine printed). The run is
cached under its own key (:data:`STATISTICS_MODE`), so runs without statistics are
never reused for it, and a rerun reads the statistics from the cache without dumping
the links again.

The statistics are defined for 2D scenes (segments): an element's geometry is its
interval ``[t0, t1]`` of arc length along its root segment.
"""

import math
import os
import tempfile
import time
from dataclasses import dataclass

import numpy as np

from .engine import run_engine
from .errors import AnalysisError
from .loader import ResultFormatError, read_links_csv
from .loader import read_scene_segments as loader_scene_segments

__all__ = [
    "STATISTICS",
    "STATISTICS_VERSION",
    "STATISTICS_MODE",
    "RELATIVE_SLACK",
    "LinkDumpError",
    "GroupStatistics",
    "ElementStatistics",
    "StatisticsJob",
    "Measurement",
    "read_link_dump",
    "read_scene_segments",
    "element_statistics",
    "hierarchy_statistics",
    "measure",
    "stored_statistics",
    "statistics_env",
    "claim_statistics",
    "is_lemma",
]

#: The hierarchy statistics of one run, by name, with their meaning (docs/lemmas.md).
#: An *element* here is an element that has links, counted once per root patch its
#: partners lie on (for two plates: once); its partners are the elements it is linked
#: with there. A *stretch* is the part of an element's partners on one side of its foot
#: point on that patch. ``A`` is the element's size, ``r`` a centre distance to a
#: partner, ``D`` the summed size of the partners (of the element, or of the stretch).
STATISTICS = {
    "leaf_min_size": "size of the smallest leaf, the smallest element with a link "
                     "(scene units)",
    "partners_max": "most partners of one element (count)",
    "partners_mean": "mean partners per element, 2 L / elements for two patches (count)",
    "partners_min": "fewest partners of one element (count)",
    "span_per_size_max": "largest D / A over the elements, D summed over both sides "
                         "(dimensionless)",
    "span_per_size_mean": "mean D / A over the elements (dimensionless)",
    "span_lower_min": "smallest D / (r_max - r_min) over the stretches with r_max > "
                      "r_min; at least 1 where D >= r_max - r_min holds (dimensionless)",
    "span_upper_max": "largest D / (r_max + r_min) over the stretches; at most 1 where "
                      "D <= r_max + r_min holds (dimensionless)",
    "span_violations": "stretches whose D breaks r_max - r_min <= D <= r_max + r_min "
                       "(count)",
    "both_sides_upper_max": "largest D / (r_max + r_min) over the elements, D and r over "
                            "both sides together (dimensionless)",
    "both_sides_violations": "elements whose D, r_min and r_max over both sides break "
                             "r_max - r_min <= D <= r_max + r_min (count)",
    "extent_violations": "elements whose extent E (max t1 - min t0 of all their "
                         "partners) breaks r_max - r_min <= E <= r_max + r_min (count)",
    "elements": "elements with links, once per patch of partners (count)",
    "stretches": "stretches: elements with links, once per patch and side (count)",
}
#: The statistics that count something: 0, not undefined, for a run without links.
_COUNTS = ("span_violations", "both_sides_violations", "extent_violations", "elements",
           "stretches")

#: Version of the definitions; part of the cache key, so a change of a definition never
#: reuses statistics measured under the old one.
STATISTICS_VERSION = 2
#: The ``mode`` of the cache key of a run with statistics (``"count-only"`` without).
STATISTICS_MODE = f"count-only+hierarchy-statistics-v{STATISTICS_VERSION}"
#: Relative slack of the inequality checks, for rounding: a group breaks the bounds
#: only when ``D`` lies outside them by more than this times ``r_max + r_min``.
RELATIVE_SLACK = 1e-9

class LinkDumpError(AnalysisError, ValueError):
    """A link list or scene that the statistics cannot be measured on."""


# ---------------------------------------------------------------------------------------
# Reading.


def read_link_dump(path):
    """Read the columns of a 2D link list (``hrbench links --out``) that the statistics need.

    Read by :func:`hrbench_analysis.loader.read_links_csv`, the one reader of link lists.

    Parameters
    ----------
    path : str or path-like
        CSV with header ``root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j``
        (other columns are ignored).

    Returns
    -------
    columns : dict of str to ndarray
        ``root_i``, ``root_j`` (int), ``t0_i``, ``t1_i``, ``t0_j``, ``t1_j`` (float, arc
        length along the root from its start point, scene units), one entry per link.

    Raises
    ------
    LinkDumpError
        If the file is not a regular file of at most
        :data:`hrbench_analysis.loader.MAX_LINKS_BYTES` bytes, a column is missing (a 3D
        link list has no ``t0``/``t1``), or a value is not a finite number (an engine's
        ``nan`` would otherwise make every bound hold or fail at random), a root index not
        an integer ``>= 0`` or an element's ``t0`` above its ``t1``.
    """
    try:
        table = read_links_csv(path)
    except ResultFormatError as exc:
        raise LinkDumpError(str(exc)) from None
    return {"root_i": table.root_i.astype(np.int64), "t0_i": table.t0_i, "t1_i": table.t1_i,
            "root_j": table.root_j.astype(np.int64), "t0_j": table.t0_j, "t1_j": table.t1_j}


def read_scene_segments(text):
    """The root segments of a 2D scene, from ``hrbench save``: as
    :func:`hrbench_analysis.loader.read_scene_segments` reads them, with
    :class:`LinkDumpError` for a scene they cannot be measured on."""
    return loader_scene_segments(text, LinkDumpError)


# ---------------------------------------------------------------------------------------
# The statistics.


@dataclass
class GroupStatistics:
    """Per-group quantities of one refinement.

    A group is an element together with the root patch its partners lie on (for two
    plates, simply an element that has links) and, for a *stretch*, the side of the
    element's foot point on that patch its partners lie on. The partners of a group are
    the elements it is linked with (on that patch, on that side).

    Attributes
    ----------
    root, partner_root : ndarray of int
        Root patch of the element and of its partners.
    side : ndarray of int
        0 for an element's group (partners on both sides), -1 for its stretch before its
        foot point on the partner patch (smaller arc length), +1 for the stretch at and
        after it.
    t0, t1 : ndarray of float
        The element's interval along its root (scene units).
    size : ndarray of float
        ``A = t1 - t0`` (scene units).
    partners : ndarray of int
        Number of partners.
    r_min, r_max : ndarray of float
        Smallest and largest centre distance to a partner (scene units).
    span : ndarray of float
        ``D``: summed size of the partners, the length of their union, since the
        partners of one element are disjoint (the links of a root pair tile it)
        (scene units).
    extent : ndarray of float
        ``E``: ``max t1 - min t0`` of the partners, the hull of their union along the
        partner patch (scene units).
    """

    root: np.ndarray
    partner_root: np.ndarray
    side: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    size: np.ndarray
    partners: np.ndarray
    r_min: np.ndarray
    r_max: np.ndarray
    span: np.ndarray
    extent: np.ndarray

    def __len__(self):
        return len(self.size)

    def violations(self, which="span", slack=RELATIVE_SLACK):
        """Which groups break ``r_max - r_min <= D <= r_max + r_min``.

        Parameters
        ----------
        which : {"span", "extent"}
            Check ``D`` (:attr:`span`) or ``E`` (:attr:`extent`).
        slack : float, optional
            Relative slack for rounding (:data:`RELATIVE_SLACK`).

        Returns
        -------
        broken : ndarray of bool
        """
        value = self.span if which == "span" else self.extent
        tol = slack * (self.r_max + self.r_min)
        return (value < self.r_max - self.r_min - tol) | (value > self.r_max + self.r_min + tol)


@dataclass
class ElementStatistics:
    """The groups of one refinement: per element, and per stretch (element and side).

    Attributes
    ----------
    elements : GroupStatistics
        One entry per element and partner patch (``side`` 0).
    stretches : GroupStatistics
        One entry per element, partner patch and side (``side`` -1 or +1) that has
        partners.
    """

    elements: GroupStatistics
    stretches: GroupStatistics


def _frame(roots, a, b):
    # Start point, unit direction and length of the root segments `roots`.
    if roots.size and (roots.min() < 0 or roots.max() >= len(a)):
        raise LinkDumpError(f"link list names root {int(roots.max())}, but the scene has "
                            f"{len(a)} patches")
    start, end = a[roots], b[roots]
    length = np.linalg.norm(end - start, axis=1)
    return start, (end - start) / np.where(length > 0, length, 1.0)[:, None]


def _groups(order, new_group, side, own, other, r):
    # Reduce the rows (one per element and partner), sorted by `order`, over the groups
    # that start where `new_group` (in sorted order) is true.
    starts = np.flatnonzero(new_group)
    at = order[starts]
    r, lo, hi = r[order], other["t0"][order], other["t1"][order]
    return GroupStatistics(
        root=own["root"][at], partner_root=other["root"][at], side=side[at],
        t0=own["t0"][at], t1=own["t1"][at], size=own["t1"][at] - own["t0"][at],
        partners=np.diff(np.append(starts, len(order))),
        r_min=np.minimum.reduceat(r, starts), r_max=np.maximum.reduceat(r, starts),
        span=np.add.reduceat(hi - lo, starts),
        extent=np.maximum.reduceat(hi, starts) - np.minimum.reduceat(lo, starts))


def element_statistics(links, a, b):
    """The per-group quantities of the lemmas, from a link list and the root segments.

    Every link ``(i, j)`` makes ``j`` a partner of ``i`` and ``i`` a partner of ``j``;
    elements are identified by root and interval. The foot point of an element on a
    partner patch is the projection of its centre onto the patch's line; a partner lies
    before it when its centre's arc length is smaller (by more than ``1e-9`` of its size),
    else at or after it.

    Parameters
    ----------
    links : dict of str to ndarray
        As from :func:`read_link_dump`.
    a, b : ndarray, shape (n, 2)
        Root segments, as from :func:`read_scene_segments`.

    Returns
    -------
    stats : ElementStatistics
        Groups sorted by root, interval, partner root (and side).
    """
    own = {k: np.concatenate([links[f"{k}_i"], links[f"{k}_j"]]) for k in ("root", "t0", "t1")}
    other = {k: np.concatenate([links[f"{k}_j"], links[f"{k}_i"]]) for k in ("root", "t0", "t1")}
    own_start, own_unit = _frame(own["root"], a, b)
    other_start, other_unit = _frame(other["root"], a, b)
    own_centre = own_start + own_unit * (0.5 * (own["t0"] + own["t1"]))[:, None]
    other_mid = 0.5 * (other["t0"] + other["t1"])
    other_centre = other_start + other_unit * other_mid[:, None]
    r = np.linalg.norm(own_centre - other_centre, axis=1)
    foot = np.einsum("ij,ij->i", own_centre - other_start, other_unit)
    side = np.where(other_mid < foot - 1e-9 * (other["t1"] - other["t0"]), -1, 1)
    del own_start, own_unit, other_start, other_unit, own_centre, other_centre, foot
    # One sort serves both groupings: an element's rows, then its stretches' rows.
    columns = [own["root"], own["t0"], own["t1"], other["root"]]
    order = np.lexsort([side, *columns[::-1]])
    new_element = np.zeros(len(order), dtype=bool)
    new_element[:1] = True
    for column in columns:
        sorted_column = column[order]
        new_element[1:] |= sorted_column[1:] != sorted_column[:-1]
    new_stretch = new_element.copy()
    sorted_side = side[order]
    new_stretch[1:] |= sorted_side[1:] != sorted_side[:-1]
    return ElementStatistics(
        elements=_groups(order, new_element, np.zeros_like(side), own, other, r),
        stretches=_groups(order, new_stretch, side, own, other, r))


def _number(value):
    # A float for JSON: None where undefined (no groups, no spread).
    value = float(value)
    return value if math.isfinite(value) else None


def hierarchy_statistics(stats):
    """The scalars of :data:`STATISTICS` from the per-group quantities.

    Parameters
    ----------
    stats : ElementStatistics

    Returns
    -------
    values : dict of str to (float, int or None)
        In the order of :data:`STATISTICS`; ``None`` where a statistic is undefined (no
        links; ``span_lower_min`` when no stretch has ``r_max > r_min``).
    """
    el, st = stats.elements, stats.stretches
    if len(el) == 0:
        return {name: (0 if name in _COUNTS else None) for name in STATISTICS}
    ratio = el.span / el.size
    spread = st.r_max > st.r_min
    return {
        "leaf_min_size": _number(el.size.min()),
        "partners_max": int(el.partners.max()),
        "partners_mean": _number(el.partners.mean()),
        "partners_min": int(el.partners.min()),
        "span_per_size_max": _number(ratio.max()),
        "span_per_size_mean": _number(ratio.mean()),
        "span_lower_min": (_number(np.min(st.span[spread] / (st.r_max - st.r_min)[spread]))
                           if spread.any() else None),
        "span_upper_max": _number(np.max(st.span / (st.r_max + st.r_min))),
        "span_violations": int(st.violations("span").sum()),
        "both_sides_upper_max": _number(np.max(el.span / (el.r_max + el.r_min))),
        "both_sides_violations": int(el.violations("span").sum()),
        "extent_violations": int(el.violations("extent").sum()),
        "elements": len(el),
        "stretches": len(st),
    }


# ---------------------------------------------------------------------------------------
# Measuring a sweep point.


@dataclass(frozen=True)
class StatisticsJob:
    """The commands that measure the statistics of one sweep point.

    Attributes
    ----------
    save_argv : tuple of str
        ``hrbench save SCENE params...``: the scene's patches as JSON.
    links_argv : tuple of str
        ``hrbench links SCENE params... --eps E ...`` without ``--out``, with the same
        oracle, limits and options as the point's run.
    """

    save_argv: tuple
    links_argv: tuple

    @classmethod
    def of(cls, run, hrbench):
        """The commands that measure the statistics of `run` (a
        :class:`~hrbench_analysis.engine.RunSpec`): its scene, and its link list with the
        same oracle, limits and options, less ``method`` (``links`` enumerates)."""
        return cls(tuple(run.save_argv(hrbench)),
                   tuple(run.without_options("method").links_argv(hrbench)))


@dataclass
class Measurement:
    """What :func:`measure` found.

    Attributes
    ----------
    statistics : dict or None
        As from :func:`hierarchy_statistics`; ``None`` when it failed.
    exit_code : int
        0, or the exit code of the engine command that failed (1 when the link list does
        not match the run).
    message : str
        Why it failed ("" when it did not).
    wall_seconds : float
        Wall time of the commands and the computation (s).
    """

    statistics: object
    exit_code: int
    message: str
    wall_seconds: float


def measure(job, links=None, timeout=None, tag=None):
    """Dump the links of one point into a temporary file and measure its statistics.

    Parameters
    ----------
    job : StatisticsJob
    links : int, optional
        The number of links the point's run counted: the link list must have as many
        rows.
    timeout : float, optional
        Seconds each of the two engine commands may take (default: no limit).
    tag : str, optional
        Names the two runs (:func:`hrbench_analysis.engine.run_engine`).

    Returns
    -------
    measurement : Measurement
        The temporary link list is deleted in every case.
    """
    start = time.perf_counter()

    def failed(code, message):
        return Measurement(None, code, message, time.perf_counter() - start)

    save = run_engine(job.save_argv, timeout, tag)
    if save.exit_code != 0:
        return failed(save.exit_code, f"hrbench save failed: {save.message or 'no message'}")
    with tempfile.TemporaryDirectory(prefix="hrbench-links-") as tmp:
        out = os.path.join(tmp, "links.csv")
        dump = run_engine([*job.links_argv, "--out", out], timeout, tag)
        if dump.exit_code != 0:
            return failed(dump.exit_code,
                          f"hrbench links failed: {dump.message or 'no message'}")
        try:
            a, b = read_scene_segments(save.stdout)
            table = read_link_dump(out)
            stats = element_statistics(table, a, b)
        except (LinkDumpError, OSError) as exc:
            return failed(1, f"hierarchy statistics: {exc}")
    rows = len(table["root_i"])
    if links is not None and rows != links:
        return failed(1, f"hierarchy statistics: the link list has {rows} links, the run "
                      f"counted {links}")
    return Measurement(hierarchy_statistics(stats), 0, "", time.perf_counter() - start)


def stored_statistics(statistics):
    """The statistics as the results cache keeps them, beside the run's record
    (:attr:`hrbench_analysis.store_points.StoredPoint.statistics`).

    Parameters
    ----------
    statistics : dict
        As from :func:`hierarchy_statistics`.

    Returns
    -------
    stored : dict
        The same values, with the ``version`` of their definitions
        (:data:`STATISTICS_VERSION`) first.
    """
    return {"version": STATISTICS_VERSION, **statistics}


def statistics_env(stored):
    """The statistics a stored point holds, for a formula, or ``None``.

    Parameters
    ----------
    stored : dict or None
        :attr:`hrbench_analysis.store_points.StoredPoint.statistics`.

    Returns
    -------
    env : dict of str to float or None
        Every name of :data:`STATISTICS` (``nan`` where undefined); ``None`` when the
        point has no statistics of this :data:`STATISTICS_VERSION`.
    """
    if not isinstance(stored, dict) or stored.get("version") != STATISTICS_VERSION:
        return None
    env = {}
    for name in STATISTICS:
        value = stored.get(name)
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        env[name] = float(value) if ok else math.nan
    return env


def claim_statistics(claim):
    """The hierarchy statistics a claim's formulas read.

    Parameters
    ----------
    claim : Claim

    Returns
    -------
    names : frozenset of str
    """
    return frozenset((claim.x.names | claim.y.names) & STATISTICS.keys())


def is_lemma(claim):
    """Whether a claim states a lemma of a proof (its id or statement says ``lemma``)."""
    return "lemma" in claim.id.lower() or "lemma" in claim.statement.lower()
