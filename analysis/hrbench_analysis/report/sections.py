"""What the Markdown and HTML pages share: the claims table's columns, the contents and
its anchors, where each figure goes, and the lines of a claim's section."""

import os

import numpy as np

from ..engine import option_argv
from ..summary import GROUPS
from ..verdict import SKIPPED

#: What each kind of claim means, for its section (the kinds of
#: :data:`hrbench_analysis.claimfile.KINDS`).
KIND_TEXT = {
    "stated": "the source's own law, in the source's own quantity",
    "reading": "the source's law in a quantity hrbench chose where the source does not "
               "fix it (the choice is stated below)",
    "derived": "hrbench's own law (a derivation, a carry-over, or a measurement without a "
               "published value), not counted as published",
}

# The columns of the claims table in the report: (row key, header).
_COLUMNS = (("id", "claim"), ("source", "source"), ("kind", "kind"),
            ("statement", "statement"),
            ("expected", "expected k"), ("measured", "measured k"), ("interval", "interval"),
            ("verdict", "verdict"), ("expected_to_hold", "should hold"),
            ("agrees", "as expected"))


# The anchor of each group's section, by its heading.
_GROUP_ANCHORS = {title: f"group-{key}" for key, title in GROUPS}


def _contents(rows, placed):
    # The table of contents: (anchor, title, [(claim id, anchor), ...]) per section.
    members = {}
    for r in rows:
        members.setdefault(r["group"], []).append((r["id"], r["anchor"]))
    entries = [("run", "Run", []), ("claims", "Claims table", [])]
    entries += [(_GROUP_ANCHORS[title], title, members[title])
                for _, title in GROUPS if title in members]
    if placed.get(None):
        entries.append(("figures", "Figures", []))
    return entries


def _place_figures(outcomes, figures):
    # Claim id -> the figures shown in its section (each in the first claim it
    # illustrates that the report lists); None -> the rest, shown at the end.
    listed = [o.claim.id for o in outcomes]
    placed = {}
    for f in figures:
        home = next((cid for cid in listed if cid in f.claims), None)
        placed.setdefault(home, []).append(f)
    return placed


def _scene_text(claim):
    # The family's name, or the mesh file's.
    return f"mesh {os.path.basename(claim.mesh)}" if claim.mesh else claim.scene


def _context_lines(context):
    return [f"- {k}: {v}" for k, v in context.items()]


def _details(o):
    a, c = o.assessment, o.claim
    options = option_argv(c.options_for(o.mode))
    measured = (f"- what is measured: y = `{c.y.text}` against x = `{c.x.text}`, "
                f"{_scene_text(c)} {', '.join(f'{k}={v:g}' for k, v in c.params.items())}"
                + (f", eps={c.eps:g}" if c.eps is not None else "")
                + (f", min_area={c.min_area:g}" if c.min_area is not None else "")
                + (f", max_depth={c.max_depth}" if c.max_depth is not None else "")
                + f", oracle {c.oracle}"
                + (f", options `{' '.join(options)}`" if options else "")
                + (", each point solved (`hrbench solve`)" if c.command == "solve" else "")
                + f", {c.sweep_param} swept"
                + "".join(f" for each {name} in {{{', '.join(f'{v:g}' for v in values)}}}"
                          for name, values in c.grid.items()))
    statement = f"- statement: `{c.statement}` ({c.source})"
    if not c.published:
        statement += (f"; no published value: the exponent {c.expected_exponent:g} is this "
                      "project's hypothesis, reported as a measurement")
    origin = [statement, f"- kind: **{c.kind}**: {KIND_TEXT[c.kind]}"]
    if c.words:
        origin.append(f"- the source's words ({c.words_at or 'where: not given'}): "
                      f"\"{c.words}\"")
    elif c.published:
        origin.append("- the source's words: not quoted in the claims file")
    else:
        origin.append("- the source's words: none: no source states this law")
    if c.quantity:
        origin.append(f"- quantity: {c.quantity}")
    if a.verdict == SKIPPED:
        return [*origin, measured,
                f"- **skipped**: {a.reason}; no point was run"]
    lines = [*origin, measured,
             f"- regime: {_regime(c)}; {a.n_regime} of {a.x.size} points, "
             f"{a.decades:.2f} decades",
             f"- verdict: **{a.verdict}** ({a.reason})"]
    if a.alternatives:
        lines.append(f"- alternatives: the test {a.refutes_text}")
    if a.fit:
        f = a.fit
        lines.append(f"- fit: y = {f.prefactor:.4g} x^{f.exponent:.4f}, RMS {f.rms:.4f} "
                     f"decades; statistical 95% interval [{f.low:.4f}, {f.high:.4f}] "
                     f"(moving-block residual bootstrap, block {f.block} points, "
                     f"{f.n_boot} resamples, seed {f.seed})")
    if a.interval and a.interval.windows.slope.size:
        iv = a.interval
        lines.append(f"- interval [{iv.low:.4f}, {iv.high:.4f}]: {iv.windows.slope.size} "
                     f"windows of {iv.window_octaves} octaves give exponents "
                     f"{iv.windows.slope.min():.3f} to {iv.windows.slope.max():.3f}; the upper "
                     f"half of them averages {iv.upper:.3f}, {iv.drift:+.3f} from the lower "
                     f"half")
    if a.windows is not None and a.windows.slope.size:
        lines.append(f"- window exponents ({a.windows.width:g} decade): "
                     f"{a.windows.slope.min():.3f} to {a.windows.slope.max():.3f}; their mean over "
                     f"the upper half lies {a.settle_spread:.3f} from the fit (settled: "
                     f"{'yes' if a.settled else 'no'})")
    if a.theta:
        t = a.theta
        lines.append(f"- Theta check: y/x^{t.exponent:g} varies by a factor {t.band:.3f} "
                     f"(bounded if at most {t.max_band:g}), trend {t.trend:+.4f} per decade "
                     f"(flat if within {t.tolerance:g})")
    if a.models:
        m = a.models
        order = np.argsort(m.delta_aic)[:4]
        lines.append("- models by AIC: " + ", ".join(
            f"{m.names[i]} (dAIC {m.delta_aic[i]:.1f})" for i in order))
    for f in o.data.failures:
        lines.append(f"- FAILED point {c.sweep_param}={f['value']:g}: exit code "
                     f"{f['exit_code']}: {f['stderr']} (`hrbench {f['command']}`)")
    return lines


def _regime(c):
    parts = []
    if c.x_min is not None:
        parts.append(f"x >= {c.x_min:g}")
    if c.x_max is not None:
        parts.append(f"x <= {c.x_max:g}")
    return " and ".join(parts) if parts else "all points"

