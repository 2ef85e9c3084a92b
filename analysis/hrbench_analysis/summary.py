"""How the report presents its claims as a whole: their order, groups, sources and tally."""

import hashlib
import re
from collections import Counter

from .verdict import SKIPPED, UNFALSIFIABLE, VERDICTS

__all__ = [
    "SEED_CLAIMS",
    "GROUPS",
    "TIMED_MARK",
    "claim_group",
    "report_order",
    "source_label",
    "claim_anchors",
    "distinct_names",
    "verdict_tally",
    "timed_tally",
    "tally_lines",
]

#: The seed paper's claims, in its numbering: Garmann & Müller's C1, C2 and C4, and C3,
#: the linear law of Hanrahan et al. that the paper sets against C4.
SEED_CLAIMS = ("C1", "C2", "C3", "C4")

#: The groups of :func:`claim_group`, in order: (anchor, heading).
GROUPS = (("seed", "The seed paper's claims C1 to C4 (Garmann & Müller 2003)"),
          ("published", "Other published claims"),
          ("own", "hrbench's own laws and measurements"),
          ("timed", "Timings: claims on CPU time, which depends on the machine and its load"))

#: The mark of a claim whose x or y is a time (:attr:`~hrbench_analysis.claimfile.Claim.timed`).
TIMED_MARK = "†"

# A publication year in a citation: 1800 to 2099.
_YEAR = re.compile(r"\b(?:1[89]|20)\d\d\b")


def claim_group(claim):
    """The report's group of a claim, an index into :data:`GROUPS`.

    Returns
    -------
    group : int
        3 for the claims whose x or y is a time (:attr:`Claim.timed
        <hrbench_analysis.claimfile.Claim.timed>`), whose points change with the machine's
        load, so that they never share a section or a tally with the others; 2 for
        hrbench's own laws and measurements, the claims without a published exponent
        (``published = false``), whatever their source says; 0 for the seed paper's
        claims (:data:`SEED_CLAIMS`); 1 for every other published claim.
    """
    if claim.timed:
        return 3
    if not claim.published:
        return 2
    return 0 if claim.id in SEED_CLAIMS else 1


def report_order(outcomes):
    """The claims in the order the report lists them.

    The seed paper's claims C1 to C4 first, in that order; then the other published
    claims; then hrbench's own laws and measurements (:func:`claim_group`). Within a group
    the claims keep the order of their files (files by name), except that claims on the
    solved radiosity (``command = "solve"``: its accuracy) come last.

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome

    Returns
    -------
    ordered : list of ClaimOutcome
    """
    def key(outcome):
        claim = outcome.claim
        group = claim_group(claim)
        seed = SEED_CLAIMS.index(claim.id) if group == 0 else 0
        return group, seed, claim.command == "solve"

    return sorted(outcomes, key=key)


def source_label(claim, short=False):
    """Who states a claim, in a few words.

    Parameters
    ----------
    claim : Claim
    short : bool, optional
        The first author only (for the terminal).

    Returns
    -------
    label : str
        ``"hrbench"`` for the benchmark's own claims (``published = false``);
        else the authors' surnames and the year of a citation of the form ``"R. Garmann,
        H. Müller: title, ..., 2003"``: ``"Garmann & Müller 2003"``, ``"Hanrahan et al.
        1991"`` (``"Garmann 2003"``, ``"Hanrahan 1991"`` when `short`); the source key of
        a citation of another form.
    """
    if not claim.published:
        return "hrbench"
    authors, colon, rest = claim.source.partition(":")
    year = _YEAR.search(rest)
    parts = [part.split() for part in re.split(r",|&|\band\b", authors)]
    names = [words[-1] for words in parts if words]
    if not colon or year is None or not names or any(len(words) > 4 for words in parts):
        return claim.source_key
    if short or len(names) == 1:
        who = names[0]
    elif len(names) == 2:
        who = f"{names[0]} & {names[1]}"
    else:
        who = f"{names[0]} et al."
    return f"{who} {year.group()}"


def claim_anchors(claims):
    """The anchor of every claim's section in the report.

    Parameters
    ----------
    claims : sequence of Claim

    Returns
    -------
    anchors : dict of str to str
        Claim id to its :func:`distinct_names` name with prefix ``claim``:
        ``"claim-c1-3d"`` for ``"C1-3d"``.
    """
    return distinct_names([claim.id for claim in claims], "claim")


def distinct_names(texts, prefix):
    """Names for texts (claim ids) as anchors and file names: distinct texts, distinct names.

    A name is `prefix` and the text's words, in lower case, joined by dashes (a word a
    run of letters and digits): ``"slopes-c1-3d"`` for ``"C1-3d"``. Where texts of one
    call give the same name (``R1`` and ``r1``, ``R-1`` and ``R.1``), each of them gets
    ``--`` and the first 8 hex digits of the SHA-256 of its text added, which no plain
    name holds: so a name depends on its text and on the others that share it only, not
    on their order.

    Parameters
    ----------
    texts : iterable of str
    prefix : str

    Returns
    -------
    names : dict of str to str
    """
    plain = {}
    for text in texts:
        words = "".join(ch if ch.isalnum() else " " for ch in text.lower()).split()
        plain[text] = "-".join([prefix, *words])
    shared = Counter(plain.values())
    return {text: name if shared[name] == 1 else
            f"{name}--{hashlib.sha256(text.encode('utf-8', 'surrogatepass')).hexdigest()[:8]}"
            for text, name in plain.items()}


def verdict_tally(outcomes):
    """The line that tells whether a reproduction matches: the verdicts of the claims on
    counts and errors, and the claims not as expected.

    The claims on timings (:attr:`Claim.timed <hrbench_analysis.claimfile.Claim.timed>`)
    are left out: their verdicts change with the machine's load, and this line must not
    (:func:`timed_tally` counts them).

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome

    Returns
    -------
    line : str
        E.g. ``"62 claims: reproduced 38, refuted 3, inconclusive 3, measured 18; not as
        expected: none"``: every verdict of :data:`~hrbench_analysis.verdict.VERDICTS`
        (``unfalsifiable`` only if any), then ``skipped`` if any; then the claims whose
        verdict is not what their file expects (``ClaimOutcome.agrees`` false), five at
        most by name.
    """
    return _tally([o for o in outcomes if not o.claim.timed], "claim")


def timed_tally(outcomes):
    """The tally of the claims on timings, apart from :func:`verdict_tally`'s, or ``None``.

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome

    Returns
    -------
    line : str or None
        E.g. ``"3 timed claims (CPU time, which depends on the machine's load; not in the
        line above): measured 3; not as expected: none"``; ``None`` when no claim is
        timed.
    """
    timed = [o for o in outcomes if o.claim.timed]
    if not timed:
        return None
    head, rest = _tally(timed, "timed claim").split(": ", 1)
    return f"{head} (CPU time, which depends on the machine's load; not in the line above): {rest}"


def tally_lines(outcomes):
    """The tally as the report and the terminal end with it: :func:`verdict_tally`, then
    :func:`timed_tally` where a claim is timed.

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome

    Returns
    -------
    lines : list of str
        One or two lines.
    """
    timed = timed_tally(outcomes)
    return [verdict_tally(outcomes), *([timed] if timed else [])]


def _tally(outcomes, noun):
    # "N nouns: verdict n, ...; not as expected: ids".
    counts = Counter(o.assessment.verdict for o in outcomes)
    parts = [f"{v} {counts[v]}" for v in VERDICTS if v != UNFALSIFIABLE or counts[v]]
    if counts[SKIPPED]:
        parts.append(f"{SKIPPED} {counts[SKIPPED]}")
    against = [o.claim.id for o in report_order(outcomes) if o.agrees is False]
    named = ", ".join(against[:5]) + (f" and {len(against) - 5} more" if len(against) > 5
                                      else "")
    n = len(outcomes)
    return (f"{n} {noun}{'' if n == 1 else 's'}: {', '.join(parts)}; not as expected: "
            f"{named or 'none'}")
