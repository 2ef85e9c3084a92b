"""The Markdown report (``report.md``): the tally, the contents, the run, the claims table,
one section per group of claims, the figures of no claim."""

from ..summary import tally_lines
from .sections import _COLUMNS, _GROUP_ANCHORS, _context_lines, _details

__all__ = ["markdown_report"]


def markdown_report(outcomes, rows, context, placed, contents, note):
    """The text of ``report.md``.

    Parameters
    ----------
    outcomes : list of ClaimOutcome
        In the report's order.
    rows : list of dict
        Their claims table (:func:`~hrbench_analysis.report.get_claims_table`).
    context : dict of str to str
        Facts about the run.
    placed : dict
        Claim id (or None) -> the figures shown in its section.
    contents : list of tuple
        The table of contents: (anchor, title, [(claim id, anchor), ...]) per section.
    note : list of str
        Lines below the claims table (the note on the timed claims, or none).
    """
    tally, *timed = tally_lines(outcomes)
    md = ["# hrbench: reproduction of published complexity claims", "",
          f"**{tally}**", "", *(line for t in timed for line in (t, "")),
          "## Contents", ""]
    md += [f"- {_md_link(title, anchor)}"
           + (": " + ", ".join(_md_link(*claim) for claim in claims) if claims else "")
           for anchor, title, claims in contents]
    md += ["", '## <a id="run"></a>Run', "", *_context_lines(context), "",
           '## <a id="claims"></a>Claims', "", _md_table(rows), "", *note]
    group = None
    for o, r in zip(outcomes, rows, strict=True):
        if r["group"] != group:
            group = r["group"]
            md += [f'## <a id="{_GROUP_ANCHORS[group]}"></a>{group}', ""]
        md += [f'### <a id="{r["anchor"]}"></a>{o.claim.id}: {o.claim.statement}', "",
               o.claim.description, "", *_details(o), ""]
        for f in placed.get(o.claim.id, []):
            md += [f"#### {f.title}", "", f"![{f.title}](plots/{f.name}.png)", "",
                   f.caption, ""]
    if placed.get(None):
        md += ['## <a id="figures"></a>Figures', ""]
    for f in placed.get(None, []):
        md += [f"### {f.title}", "", f"![{f.title}](plots/{f.name}.png)", "", f.caption, ""]
        if f.alternate is not None:
            a = f.alternate
            md += [f"#### {a.title}", "", f"![{a.title}](plots/{a.name}.png)", ""]
    return "\n".join(md)


def _md_text(text):
    # Text that stays text in a Markdown table cell.
    return text.replace("|", "\\|")


def _md_link(text, anchor):
    # A link to an anchor of the report; its text escaped to stay one link in a cell.
    text = "".join("\\" + ch if ch in "\\[]|" else ch for ch in text)
    return f"[{text}](#{anchor})"


def _md_table(rows):
    head = "| " + " | ".join(h for _, h in _COLUMNS) + " |"
    rule = "|" + "|".join("---" for _ in _COLUMNS) + "|"
    body = ["| " + " | ".join(_md_link(r["id"], r["anchor"]) + r["mark"] if k == "id"
                              else _md_text(r[k]) for k, _ in _COLUMNS) + " |"
            for r in rows]
    return "\n".join([head, rule, *body])
