"""The claims table: one row per claim (:func:`get_claims_table`), and its plain-text
form for the terminal (:func:`format_claims_table`, :func:`print_claims_table`)."""

import math
import sys
import textwrap

from ..summary import (
    GROUPS,
    TIMED_MARK,
    claim_anchors,
    claim_group,
    report_order,
    source_label,
)
from ..verdict import expected_text

__all__ = [
    "KINDS_NOTE",
    "get_claims_table",
    "print_claims_table",
    "format_claims_table",
    "claims_table_lines",
    "TERMINAL_WIDTH",
    "TIMED_NOTE",
]


def _num(value, digits=3):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value:.{digits}f}"


def get_claims_table(outcomes):
    """One row per claim, ready to print, in the report's order
    (:func:`~hrbench_analysis.summary.report_order`).

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome

    Returns
    -------
    rows : list of dict
        Keys ``id``, ``anchor`` (of the claim's section), ``mark`` (:data:`TIMED_MARK` for
        a claim that times the CPU, else empty), ``statement``, ``source`` and
        ``source_short`` (who states it, :func:`~hrbench_analysis.summary.source_label`),
        ``citation``, ``group`` (its heading, :data:`~hrbench_analysis.summary.GROUPS`),
        ``kind`` (``stated``, ``reading`` or ``derived``),
        ``expected``, ``measured``, ``interval``, ``verdict``, ``expected_to_hold``,
        ``agrees``, ``reason`` (strings).
    """
    outcomes = report_order(outcomes)
    anchors = claim_anchors([o.claim for o in outcomes])
    rows = []
    for o in outcomes:
        a, c = o.assessment, o.claim
        fit, iv = a.fit, a.interval
        rows.append({
            "id": c.id,
            "anchor": anchors[c.id],
            "mark": TIMED_MARK if c.timed else "",
            "statement": c.statement,
            "source": source_label(c),
            "source_short": source_label(c, short=True),
            "citation": c.source,
            "group": GROUPS[claim_group(c)][1],
            "kind": c.kind,
            "expected": expected_text(c),
            "measured": _num(fit.exponent) if fit else "-",
            "interval": f"[{_num(iv.low)}, {_num(iv.high)}]" if iv else "-",
            "verdict": a.verdict,
            "expected_to_hold": "yes" if c.expected_to_hold else "no",
            "agrees": {True: "yes", False: "NO", None: "-"}[o.agrees],
            "reason": a.reason,
        })
    return rows


#: Columns of the claims table on the terminal.
TERMINAL_WIDTH = 100

# The terminal's columns: (row key, header, widest); the statement, last, takes the rest
# of TERMINAL_WIDTH. The claimed exponent is in the statement and the interval in the
# reasons printed below the table, so neither has a column here.
_TERMINAL = (("claim", "claim", 18), ("source_short", "source", 13), ("kind", "kind", 7),
             ("measured", "k", 6), ("verdict", "verdict", 13), ("agrees", "as expected", 11))

#: The note on the column ``kind``, below every claims table.
KINDS_NOTE = ("kind: stated, the source's own law in its own quantity; reading, the "
              "source's law in a quantity hrbench chose (the choice is stated in the "
              "claim's section); derived, hrbench's own law, not counted as published.")

#: The note on the claims that time the CPU, below every claims table that has one.
TIMED_NOTE = (f"{TIMED_MARK} times the CPU: its x or y is a time (s), which depends on the "
              "machine and its load, so its points, exponent and verdict change whenever "
              "they are measured anew (another machine, an empty cache); the other claims "
              "measure counts and errors, which do not.")


def _clip(text, width):
    # The text cut to `width` characters, at a space where one is near, an ellipsis
    # marking the cut.
    if len(text) <= width:
        return text
    cut = text[:width - 1]
    space = cut.rfind(" ")
    return (cut[:space] if space > width // 2 else cut).rstrip() + "…"


def _wrap(text):
    # The text as lines of at most TERMINAL_WIDTH characters, continuation lines
    # indented; words (formulas, paths) are never split.
    return textwrap.wrap(text, TERMINAL_WIDTH, subsequent_indent="    ",
                         break_long_words=False, break_on_hyphens=False)


def format_claims_table(rows):
    """The claims table as lines of aligned plain text, :data:`TERMINAL_WIDTH` wide at most.

    Parameters
    ----------
    rows : list of dict
        From :func:`get_claims_table`.

    Returns
    -------
    lines : list of str
        Header, rule, one line per claim (id with its mark, the first author and year of
        its source, measured exponent, verdict, whether as expected, statement cut to the
        columns left), then a line that says what ``k`` is and :data:`TIMED_NOTE` if a
        claim times the CPU. Cut cells end in an ellipsis; nothing wraps.
    """
    cells = [{**r, "claim": r["id"] + r["mark"]} for r in rows]
    widths = [min(cap, max([len(head), *(len(c[key]) for c in cells)]))
              for key, head, cap in _TERMINAL]
    # The caps leave the statement 18 columns at least.
    rest = TERMINAL_WIDTH - sum(widths) - 2 * len(widths)
    columns = [*(key for key, _, _ in _TERMINAL), "statement"]
    widths.append(rest)

    def line(values):
        return "  ".join(_clip(v, w).ljust(w) for v, w in zip(values, widths,
                                                              strict=True)).rstrip()

    lines = [line([*(head for _, head, _ in _TERMINAL), "statement"]),
             "  ".join("-" * w for w in widths)]
    lines += [line([c[key] for key in columns]) for c in cells]
    lines += _wrap("k: the measured exponent (the claimed one is in the statement, the "
                   "interval in the reasons below)")
    lines += _wrap(KINDS_NOTE)
    if any(r["mark"] for r in rows):
        lines += _wrap(TIMED_NOTE)
    return lines


def claims_table_lines(rows):
    """The claims table (:func:`format_claims_table`), a blank line, then one reason per
    claim, wrapped to :data:`TERMINAL_WIDTH` columns: what the terminal shows.

    Parameters
    ----------
    rows : list of dict
        From :func:`get_claims_table`.

    Returns
    -------
    lines : list of str
    """
    lines = [*format_claims_table(rows), ""]
    for r in rows:
        lines += _wrap(f"{r['id']}: {r['verdict']}: {r['reason']}")
    return lines


def print_claims_table(rows, file=None):
    """Print :func:`claims_table_lines`.

    Parameters
    ----------
    rows : list of dict
        From :func:`get_claims_table`.
    file : text stream, optional
        Default standard output.
    """
    file = sys.stdout if file is None else file
    for text in claims_table_lines(rows):
        print(text, file=file)
