"""The HTML report (``report.html``): the Markdown report's sections, with the figures
embedded and the claims table's verdicts coloured."""

import base64
import html

from ..summary import tally_lines
from .sections import _COLUMNS, _GROUP_ANCHORS, _details

__all__ = ["html_report"]


def html_report(outcomes, rows, context, placed, contents, note, pngs):
    """The text of ``report.html``.

    Parameters
    ----------
    outcomes, rows, context, placed, contents, note
        As for :func:`~hrbench_analysis.report.markdown_page.markdown_report`.
    pngs : dict of str to bytes
        The PNG of every figure and alternate view, by its name.
    """
    esc = html.escape
    tally, *timed = tally_lines(outcomes)
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'>",
             "<title>hrbench claims report</title><style>",
             "body{font-family:sans-serif;max-width:1250px;margin:2em auto;padding:0 1em}",
             "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px}",
             "th{background:#eee}.reproduced{background:#d8f5d8}.refuted{background:#f8d8d8}",
             ".inconclusive{background:#f5efc8}.measured{background:#dce8f5}.skipped{background:#e4e4e4}img{max-width:100%}code{background:#f4f4f4}",
             "</style></head><body>",
             "<h1>hrbench: reproduction of published complexity claims</h1>",
             f"<p><b>{esc(tally)}</b></p>", *(f"<p>{esc(t)}</p>" for t in timed),
             "<nav><h2 id='contents'>Contents</h2><ul>"]
    for anchor, title, claims in contents:
        links = ", ".join(f"<a href='#{esc(a)}'>{esc(cid)}</a>" for cid, a in claims)
        parts.append(f"<li><a href='#{esc(anchor)}'>{esc(title)}</a>"
                     + (f": {links}" if links else "") + "</li>")
    parts.append("</ul></nav><h2 id='run'>Run</h2><ul>")
    parts += [f"<li>{esc(k)}: {esc(str(v))}</li>" for k, v in context.items()]
    parts += ["</ul><h2 id='claims'>Claims</h2><table><tr>"]
    parts += [f"<th>{esc(h)}</th>" for _, h in _COLUMNS]
    parts.append("</tr>")
    for r in rows:
        parts.append(f"<tr>{''.join(_html_cell(r, k) for k, _ in _COLUMNS)}</tr>")
    parts.append("</table>")
    parts += [f"<p>{esc(line)}</p>" for line in note if line]
    def img(f):
        data = base64.b64encode(pngs[f.name]).decode("ascii")
        return f"<img alt='{esc(f.title)}' src='data:image/png;base64,{data}'>"

    def image(f, level):
        toggle = ("" if f.alternate is None else
                  f"<details><summary>{esc(f.alternate.title)}</summary>"
                  f"{img(f.alternate)}</details>")
        return (f"<h{level}>{esc(f.title)}</h{level}>{img(f)}{toggle}"
                f"<p>{esc(f.caption)}</p>")

    group = None
    for o, r in zip(outcomes, rows, strict=True):
        if r["group"] != group:
            group = r["group"]
            parts.append(f"<h2 id='{_GROUP_ANCHORS[group]}'>{esc(group)}</h2>")
        parts.append(f"<h3 id='{esc(r['anchor'])}'>{esc(o.claim.id)}: "
                     f"{esc(o.claim.statement)}</h3>")
        parts.append(f"<p>{esc(o.claim.description)}</p><ul>")
        for line in _details(o):
            text = esc(line[2:]).replace("**", "")
            parts.append(f"<li>{text.replace('`', '')}</li>")
        parts.append("</ul>")
        parts += [image(f, 4) for f in placed.get(o.claim.id, [])]
    if placed.get(None):
        parts.append("<h2 id='figures'>Figures</h2>")
    parts += [image(f, 3) for f in placed.get(None, [])]
    parts.append("</body></html>")
    return "\n".join(parts)


def _html_cell(row, key):
    # A cell of the HTML claims table: the claim links to its section, the verdict is
    # coloured by its class, the source shows its full citation on hover.
    esc = html.escape
    if key == "id":
        return f"<td><a href='#{esc(row['anchor'])}'>{esc(row['id'])}</a>{esc(row['mark'])}</td>"
    if key == "verdict":
        return f"<td class='{esc(row[key])}'>{esc(row[key])}</td>"
    if key == "source":
        return f"<td title='{esc(row['citation'])}'>{esc(row[key])}</td>"
    return f"<td>{esc(row[key])}</td>"
