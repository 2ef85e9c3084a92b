"""The report as a reader navigates it: order, groups, sources, tally, contents, anchors."""

import html.parser
import re
from collections import Counter

import numpy as np
import pytest

from hrbench_analysis.claimfile import load_claims_dir
from hrbench_analysis.report import (
    KINDS_NOTE,
    TERMINAL_WIDTH,
    TIMED_NOTE,
    ClaimOutcome,
    format_claims_table,
    get_claims_table,
    get_figures,
    print_claims_table,
    write_report,
)
from hrbench_analysis.summary import (
    TIMED_MARK,
    claim_anchors,
    claim_group,
    report_order,
    source_label,
    timed_tally,
    verdict_tally,
)
from hrbench_analysis.sweep import ClaimData
from hrbench_analysis.verdict import assess_claim, skipped_assessment

GARMANN = "R. Garmann, H. Müller: On the Computational Complexity, LNCS 2598, 2003 (tr 1995)"
HANRAHAN = "P. Hanrahan, D. Salzman, L. Aupperle: A Rapid Algorithm, SIGGRAPH 1991"


def claim(cid, k=1, statement=None, extra="", x="1/eps", y="N"):
    return f"""
[[claim]]
id = "{cid}"
statement = "{statement or f'N = Theta(x^{k}) ({cid})'}"
scene = "parallel"
params = {{ l = 8, d = 1 }}
sweep.param = "eps"
sweep.range = {{ from = 1.0, to = 0.001, per_decade = 10 }}
x = "{x}"
y = "{y}"
expected_exponent = {k}
tolerance = 0.1
{extra}
"""


# Files in name order: hrbench's own first, the seed paper's claims out of their order.
FILES = {
    "accuracy.toml": '[source]\nkey = "accuracy"\ncitation = "Measured by this benchmark"\n'
                     + claim("ACC-cpu", -0.5, extra='command = "solve"\npublished = false',
                             x="cpu_seconds_solve", y="reference_error_l2")
                     + claim("OWN-count", extra="published = false"),
    "garmann2003.toml": f'[source]\nkey = "garmann2003"\ncitation = "{GARMANN}"\n'
                        + claim("C4", 2) + claim("LEM-x") + claim("C1")
                        + claim("C2-not", extra="expected_to_hold = false"),
    "hanrahan1991.toml": f'[source]\nkey = "hanrahan1991"\ncitation = "{HANRAHAN}"\n'
                         + claim("H-short") + claim("C3")
                         + claim("HO-law", extra='source = "derived and measured by this '
                                 'benchmark"\npublished = false')
                         # A published claim whatever its source's words.
                         + claim("H-own-words", extra='source = "measured by this benchmark"'),
    "zzz.toml": '[source]\nkey = "zzz"\ncitation = "a note without authors"\n'
                + claim("Z-skip"),
}

#: The report's order of FILES' claims.
ORDER = ["C1", "C3", "C4", "LEM-x", "C2-not", "H-short", "H-own-words", "Z-skip", "OWN-count",
         "HO-law", "ACC-cpu"]


@pytest.fixture
def claims(tmp_path):
    folder = tmp_path / "claims"
    folder.mkdir()
    for name, text in FILES.items():
        (folder / name).write_text(text)
    return load_claims_dir(folder)


@pytest.fixture
def outcomes(claims):
    # Every kind of verdict: reproduced, refuted against and as expected, inconclusive,
    # unfalsifiable (H-own-words: its points lie exactly on the law), measured, skipped.
    x = np.logspace(0, 3, 31)
    out = []
    for c in claims:
        if c.id == "Z-skip":
            out.append(ClaimOutcome(c, ClaimData(x[:0], x[:0], x[:0]),
                                    skipped_assessment(c, "engine lacks scene 'zzz'")))
            continue
        k = {"C3": 2.0, "C2-not": 3.0}.get(c.id, c.expected_exponent)
        xs = x[:5] if c.id == "H-short" else x
        # A scatter of 1% makes the points a measurement; exact points are an identity.
        scatter = 1 if c.id == "H-own-words" else 1 + 0.01 * np.cos(2.3 * np.arange(xs.size))
        data = ClaimData(xs, xs, 3 * xs ** k * scatter)
        out.append(ClaimOutcome(c, data, assess_claim(c, data, n_boot=50)))
    return out


def test_groups_and_order(claims, outcomes):
    groups = {c.id: claim_group(c) for c in claims}
    assert [cid for cid, g in groups.items() if g == 0] == ["C4", "C1", "C3"]
    assert {cid for cid, g in groups.items() if g == 2} == {"OWN-count", "HO-law"}
    assert {cid for cid, g in groups.items() if g == 3} == {"ACC-cpu"}  # timed: apart
    assert groups["H-own-words"] == 1   # published: the source's words do not matter
    assert [o.claim.id for o in report_order(outcomes)] == ORDER
    assert [r["id"] for r in get_claims_table(outcomes)] == ORDER
    # The order is a function of the claims, not of the order they come in.
    assert [o.claim.id for o in report_order(outcomes[::-1])][:3] == ORDER[:3]


def test_source_labels(claims):
    by_id = {c.id: c for c in claims}
    assert source_label(by_id["C1"]) == "Garmann & Müller 2003"
    assert source_label(by_id["C1"], short=True) == "Garmann 2003"
    assert source_label(by_id["C3"]) == "Hanrahan et al. 1991"
    assert source_label(by_id["C3"], short=True) == "Hanrahan 1991"
    for own in ("ACC-cpu", "OWN-count", "HO-law"):
        assert source_label(by_id[own]) == "hrbench"
    assert source_label(by_id["Z-skip"]) == "zzz"  # a citation without "authors: title"


def test_tally_counts_every_verdict_and_names_the_unexpected(outcomes):
    line = verdict_tally(outcomes)
    # The timed claim (ACC-cpu) is counted apart, on a line of its own.
    verdicts = Counter(o.assessment.verdict for o in outcomes if o.claim.id != "ACC-cpu")
    assert verdicts == {"reproduced": 3, "refuted": 2, "inconclusive": 1, "unfalsifiable": 1,
                        "measured": 2, "skipped": 1}
    head, counts = line.split(";")[0].split(": ")
    assert head == f"{len(outcomes) - 1} claims"
    assert {name: int(n) for name, n in (part.split() for part in counts.split(", "))} == (
        verdicts)
    assert counts == ("reproduced 3, refuted 2, inconclusive 1, unfalsifiable 1, measured 2, "
                      "skipped 1")
    # C3 (its points grow like x^2) is refuted although expected to hold; C2-not is
    # refuted as its file expects.
    assert line.endswith("; not as expected: C3")
    assert verdict_tally(outcomes[:1]) == ("0 claims: reproduced 0, refuted 0, inconclusive 0, "
                                           "measured 0; not as expected: none")
    assert verdict_tally(outcomes[1:2]) == ("1 claim: reproduced 0, refuted 0, inconclusive 0, "
                                            "measured 1; not as expected: none")
    assert timed_tally(outcomes) == ("1 timed claim (CPU time, which depends on the machine's "
                                     "load; not in the line above): reproduced 0, refuted 0, "
                                     "inconclusive 0, measured 1; not as expected: none")
    assert timed_tally(outcomes[1:]) is None


def test_tally_does_not_move_with_the_timings(outcomes):
    # The timed claim's points change with the load: whatever its verdict becomes, the
    # line that says whether a reproduction matches stays the same, and so does the exit
    # code's rule (a refuted timed claim is named on its own line only).
    before = verdict_tally(outcomes)
    timed = next(o for o in outcomes if o.claim.timed)
    for verdict in ("inconclusive", "refuted", "reproduced"):
        timed.assessment.verdict = verdict
        assert verdict_tally(outcomes) == before
        assert f"{verdict} 1" in timed_tally(outcomes)


def test_anchors_are_unique_and_plain():
    class Named:
        def __init__(self, cid):
            self.id = cid

    anchors = claim_anchors([Named(i) for i in ("C1-3d", "c1 3d", "C1.3D", "HO-N", "ü?")])
    # Ids that share a plain anchor get the first 8 hex digits of their SHA-256
    # (printf 'C1-3d' | sha256sum), whatever their order.
    assert list(anchors.values()) == ["claim-c1-3d--279fd5a8", "claim-c1-3d--d3bad2b2",
                                      "claim-c1-3d--f8b2a441", "claim-ho-n", "claim-ü"]
    reversed_ids = claim_anchors([Named(i) for i in ("ü?", "HO-N", "C1.3D", "c1 3d")])
    assert reversed_ids == {"ü?": "claim-ü", "HO-N": "claim-ho-n",
                            "C1.3D": "claim-c1-3d--f8b2a441", "c1 3d": "claim-c1-3d--d3bad2b2"}
    assert claim_anchors([Named("C1-3d")]) == {"C1-3d": "claim-c1-3d"}


def test_terminal_table_fits_100_columns_and_marks_timed_claims(outcomes, capsys):
    long = next(o.claim for o in outcomes if o.claim.id == "LEM-x")
    long.id = "A-claim-id-far-longer-than-the-column"
    long.statement = "a statement " * 20
    rows = get_claims_table(outcomes)
    lines = format_claims_table(rows)
    assert TERMINAL_WIDTH == 100 and max(len(line) for line in lines) <= 100
    assert lines[0].split() == ["claim", "source", "kind", "k", "verdict", "as", "expected",
                                "statement"]
    assert set(lines[1]) <= {"-", " "} and len(lines[1]) == 100
    body = {line.split()[0]: line for line in lines[2:2 + len(rows)]}
    assert "A-claim-id-far-lo…" in body and body["A-claim-id-far-lo…"].endswith("…")
    acc = body[f"ACC-cpu{TIMED_MARK}"]
    assert "hrbench" in acc and "measured" in acc and "-0.500" in acc
    assert "Garmann 2003" in body["C1"] and "Hanrahan 1991" in body["C3"]
    assert [line.split()[0] for line in lines[2:2 + len(rows)]] == [
        r["id"][:17] + ("…" if len(r["id"]) > 18 else r["mark"]) for r in rows]
    assert sum(line.startswith(TIMED_MARK) for line in lines) == 1
    # The reasons below the table are wrapped to the same width.
    print_claims_table(rows)
    out = capsys.readouterr().out.splitlines()
    assert max(len(line) for line in out) <= 100 and len(out) > len(lines) + len(rows)
    # No claim times the CPU: no note.
    untimed = [r for r in rows if not r["mark"]]
    assert not any(line.startswith(TIMED_MARK) for line in format_claims_table(untimed))


class _Anchors(html.parser.HTMLParser):
    # The ids and the local links of an HTML page.
    def __init__(self):
        super().__init__()
        self.ids, self.links = [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.append(attrs["id"])
        if tag == "a" and attrs.get("href", "").startswith("#"):
            self.links.append(attrs["href"][1:])


def test_report_has_contents_anchors_links_tally_and_groups(tmp_path, outcomes):
    paths = write_report(tmp_path / "out", outcomes, {"mode": "quick"}, [])
    md, page = paths["markdown"].read_text(), paths["html"].read_text()
    tally = verdict_tally(outcomes)
    anchors = {r["id"]: r["anchor"] for r in get_claims_table(outcomes)}

    # Markdown: the tally and the contents come before everything else.
    lines = md.splitlines()
    assert lines[2] == f"**{tally}**" and lines[4] == timed_tally(outcomes)
    assert lines[6] == "## Contents"
    targets = re.findall(r'<a id="([^"]+)"></a>', md)
    assert len(targets) == len(set(targets))
    links = re.findall(r"\]\(#([^)]+)\)", md)
    assert set(links) == set(targets)   # every link lands, every anchor is linked
    contents = md[md.index("## Contents"):md.index('<a id="run">')]
    table = md[md.index('<a id="claims">'):md.index('<a id="group-seed">')]
    for cid, anchor in anchors.items():
        assert f"[{cid}](#{anchor})" in contents and f"| [{cid}](#{anchor})" in table
    headings = [line for line in lines if line.startswith(("## ", "### "))]
    order = [re.sub(r"<a id=\"[^\"]+\"></a>", "", h).split(":")[0][4:] for h in headings
             if h.startswith("### ")]
    assert order == ORDER
    groups = [h.split("</a>")[1] for h in headings if h.startswith("## <a id=\"group-")]
    assert groups == ["The seed paper's claims C1 to C4 (Garmann & Müller 2003)",
                      "Other published claims", "hrbench's own laws and measurements",
                      "Timings: claims on CPU time, which depends on the machine and its load"]
    assert f"| [ACC-cpu](#claim-acc-cpu){TIMED_MARK} | hrbench | derived |" in md
    assert md.count(TIMED_NOTE) == 1 and md.count(KINDS_NOTE) == 1
    assert "| [C1](#claim-c1) | Garmann & Müller 2003 | stated |" in md
    # Each section states the kind and, where a fit exists, the alternatives.
    c1 = md[md.index('<a id="claim-c1">'):md.index('<a id="claim-c3">')]
    assert "- kind: **stated**" in c1
    assert "- alternatives: the test refutes the alternative exponents 0.85 and 1.15" in c1
    own = md[md.index('<a id="claim-h-own-words">'):md.index('<a id="claim-z-skip">')]
    assert "**unfalsifiable**" in own and "could not have failed" in own

    # HTML: the same, every local link lands on a unique id.
    parser = _Anchors()
    parser.feed(page)
    assert len(parser.ids) == len(set(parser.ids))
    assert set(parser.links) <= set(parser.ids)
    assert set(anchors.values()) <= set(parser.links) and set(anchors.values()) <= set(
        parser.ids)
    assert page.index(f"<b>{tally}</b>") < page.index("id='contents'") < page.index(
        "id='run'") < page.index("id='claims'") < page.index("id='group-seed'")
    assert page.count(TIMED_NOTE) == 1
    assert f"title='{GARMANN}'" in page


def test_theta_panels_name_their_band_and_its_bound(outcomes):
    # Each claim's right panel: its legend names the points and the band, with the
    # bound its claim judges the band against; the caption says what the dashes are.
    panels = {f.claims: f for f in get_figures(outcomes) if f.name.startswith("slopes")}
    c4 = panels[("C4",)]
    ax = c4.figure.axes[1]
    assert ax.get_title().startswith("C4: Theta check")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[0] == "ratio in the regime"
    assert re.fullmatch(r"the regime's band \(min, max\): max/min \d+\.\d\d, bounded if at "
                        r"most 10", labels[-1]), labels
    assert "The dashed lines bound the regime's ratios" in c4.caption
    assert "max/min is at most 10" in c4.caption
