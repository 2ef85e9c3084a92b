"""The history page: a static, self-contained HTML page of every benchmark's time and
exact counters over the commits (:func:`write_html`)."""

import base64
import datetime as dt
import html
import io
import math
from pathlib import Path

import numpy as np

from ...output import write_file
from ..gbench import (
    format_time,
    time_unit,
)
from .steps import DEFAULT_MIN_CHANGE, DEFAULT_MIN_NOISE, DEFAULT_MIN_POINTS, DEFAULT_PENALTY
from .store import describe_range, get_counter_changes, get_step_ranges


def _format_count(x):
    return f"{int(x):,}" if float(x).is_integer() and abs(x) < 1e18 else f"{x:.6g}"


def _figure_png(bench, series, commits, changes):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import FixedLocator, NullLocator

    changed = sorted({c.counter for c in changes})
    nrows = 2 if changed else 1
    fig = Figure(figsize=(9.0, 3.2 * nrows), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, 1, sharex=True, squeeze=False)[:, 0]
    unit, scale = time_unit(np.median([p.median for s in series for p in s.points]))
    ax = axes[0]
    for s in series:
        x = np.array([p.commit_index for p in s.points])
        med = np.array([p.median for p in s.points]) / scale
        lo = np.array([p.times.min() for p in s.points]) / scale
        hi = np.array([p.times.max() for p in s.points]) / scale
        (line,) = ax.plot(x, med, "o-", ms=3.5, lw=1.2, label=f"{s.machine} (median)")
        ax.fill_between(x, lo, hi, color=line.get_color(), alpha=0.2, lw=0,
                        label=f"{s.machine} (min..max)")
        for st in s.steps:
            xi = s.points[st.index].commit_index
            ax.axvline(xi - 0.5, color=line.get_color(), ls="--", lw=1)
            ax.annotate(f"x{st.ratio:.3g}", (xi - 0.5, st.after / scale), fontsize=8,
                        xytext=(3, 3), textcoords="offset points", color=line.get_color())
    ax.set_ylabel(f"time ({unit})")
    ax.set_title(bench, fontsize=9)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    if changed:
        ax2 = axes[1]
        for s in series:
            for name in changed:
                pts = [(p.commit_index, p.counters[name]) for p in s.points
                       if name in p.counters]
                if not pts:
                    continue
                x, v = zip(*pts, strict=True)
                v = np.asarray(v, dtype=float)
                ref = v[0] if v[0] != 0 else 1.0
                ax2.plot(x, v / ref, ".-", lw=1, drawstyle="steps-mid",
                         label=f"{name} / {_format_count(ref)} ({s.machine})")
        for c in changes:
            s = next(t for t in series if t.machine == c.machine)
            ax2.axvline(s.points[c.index].commit_index - 0.5, color="0.4", ls=":", lw=1)
        ax2.set_ylabel("counter / first value")
        ax2.legend(fontsize=7, loc="best")
        ax2.grid(alpha=0.3)
    n = len(commits)
    step = max(1, math.ceil(n / 30))
    ticks = list(range(0, n, step))
    axes[-1].xaxis.set_major_locator(FixedLocator(ticks))
    axes[-1].xaxis.set_minor_locator(NullLocator())
    axes[-1].set_xticklabels([commits[i][0][:7] for i in ticks], rotation=60, fontsize=7,
                             family="monospace")
    axes[-1].set_xlim(-0.5, n - 0.5)
    axes[-1].set_xlabel("commit (commit date order)")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _machines_summary(runs):
    out = {}
    for r in runs:
        m = out.setdefault(r.label, {"runs": 0, "commits": set(), "cpu": r.machine.get(
            "cpu_model"), "cores": r.machine.get("num_cpus"), "builds": set(),
            "loads": []})
        m["runs"] += 1
        m["commits"].add(r.sha)
        m["builds"].add(str(r.build.get("library_build_type")))
        la = r.machine.get("load_avg")
        if isinstance(la, list) and la:
            m["loads"].append(float(la[0]))
    return out


def _table(headers, rows):
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def write_html(out, runs, notes, commits, series, *, metric="real_time",
               machine=None, params=None, title="hrbench benchmark history", repo="."):
    """Write the static page; return the steps and counter changes it lists.

    Parameters
    ----------
    out : path-like
        The HTML file to write (:func:`~hrbench_analysis.output.write_file`: a regular
        file replaced whole, a symbolic link's target written, a device written
        through; OutputError if the write fails, the previous page kept).
    runs, notes : as returned by `load_history` (runs already filtered by machine).
    commits, series : as returned by `get_series`.
    metric : str, optional
        The time shown.
    machine : str, optional
        The machine the page is restricted to, if any.
    params : dict, optional
        The step rule's parameters, shown on the page.
    repo : path-like, optional
        The git repository of the commits, to list those between two measured ones.

    Returns
    -------
    steps : list of StepRange
    changes : list of CounterChange
    """
    esc = html.escape
    params = params or {}
    steps = get_step_ranges(series, repo)
    changes = get_counter_changes(series)
    machines = _machines_summary(runs)

    def commit_cell(ci):
        sha, date, subject = commits[ci]
        return (f"<code title='{esc(sha)}'>{esc(sha[:10])}</code> "
                f"{esc(date.date().isoformat())} {esc(subject[:60])}")

    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{esc(title)}</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:1em auto;"
             "padding:0 1em}table{border-collapse:collapse;font-size:90%;margin:.5em 0}"
             "td,th{border:1px solid #bbb;padding:2px 6px;text-align:left}"
             ".note{background:#fff4d6;border-left:4px solid #e0a800;padding:.4em .8em}"
             "img{max-width:100%}.slower{color:#b00}.faster{color:#070}"
             "h2{margin-top:1.5em}</style></head><body>",
             f"<h1>{esc(title)}</h1>",
             f"<p>{len(runs)} runs, {len(commits)} commits, "
             f"{len({s.benchmark for s in series})} benchmarks, {esc(metric)}: median of the "
             "repetitions, min..max as a band. Generated "
             f"{dt.datetime.now(dt.UTC).strftime('%Y-%m-%d %H:%M UTC')}.</p>"]
    if machine is not None:
        parts.append(f"<p class='note'>Only machine <b>{esc(machine)}</b> is shown.</p>")
    if len(machines) > 1:
        parts.append(
            f"<p class='note'>This history holds runs of {len(machines)} machines: "
            + ", ".join(f"<b>{esc(k)}</b> ({v['runs']} runs)" for k, v in machines.items())
            + ". Each machine is its own series: times of different machines are never "
            "averaged or joined, and steps are detected per machine.</p>")
    for note in notes:
        parts.append(f"<p class='note'>{esc(note)}</p>")
    rows = [(esc(k), esc(str(v["cpu"] or "?")), esc(str(v["cores"] or "?")), v["runs"],
             len(v["commits"]), esc(", ".join(sorted(v["builds"]))),
             esc(f"{min(v['loads']):.2f}..{max(v['loads']):.2f}") if v["loads"] else "?")
            for k, v in machines.items()]
    parts.append("<h2>Machines</h2>")
    parts.append(_table(["machine", "CPU model", "cores", "runs", "commits",
                         "library build", "load avg (1 min) at start"], rows))
    parts.append("<h2 id='steps'>Detected steps</h2>")
    rule = (f"Piecewise-constant fit of the log medians, penalty "
            f"{params.get('penalty', DEFAULT_PENALTY)} &sigma;&sup2; ln n per step, "
            f"&sigma; the robust noise (at least {params.get('min_noise', DEFAULT_MIN_NOISE)}"
            f"), at least {params.get('min_points', DEFAULT_MIN_POINTS)} points on each "
            f"side, steps under {params.get('min_change', DEFAULT_MIN_CHANGE):.1%} merged. "
            "A step is credited to the commits after the last point at the old level up to "
            "the first at the new one; those not measured are listed.")
    parts.append(f"<p>{rule}</p>")
    if steps:
        rows = []
        for r in steps:
            s, st = r.series, r.step
            cls = "slower" if st.ratio > 1 else "faster"
            where = commit_cell(s.points[st.index].commit_index)
            if not (r.commits is not None and not r.unmeasured):
                where += f"<br>{esc(describe_range(r, commits))}"
            rows.append((f"<a href='#b{series.index(s)}'>{esc(s.benchmark)}</a>",
                         esc(s.machine), where,
                         f"{esc(format_time(st.before))} &rarr; {esc(format_time(st.after))}",
                         f"<span class='{cls}'>{st.ratio:.3f} ({st.ratio - 1:+.1%})</span>"))
        parts.append(_table(["benchmark", "machine", "commits", "before → after", "ratio"],
                            rows))
    else:
        parts.append("<p>No step detected.</p>")
    parts.append("<h2 id='counters'>Counter changes (algorithm changes)</h2>")
    if changes:
        rows = []
        for c in changes:
            s = next(t for t in series if t.benchmark == c.benchmark and t.machine == c.machine)
            rows.append((esc(c.benchmark), esc(c.machine),
                         commit_cell(s.points[c.index].commit_index), esc(c.counter),
                         f"{_format_count(c.before)} &rarr; {_format_count(c.after)}"))
        parts.append(_table(["benchmark", "machine", "commit", "counter", "before → after"],
                            rows))
    else:
        parts.append("<p>No exact counter changed between commits.</p>")
    by_bench = {}
    for s in series:
        by_bench.setdefault(s.benchmark, []).append(s)
    parts.append("<h2>Benchmarks</h2>")
    for bench, ss in by_bench.items():
        bench_changes = [c for c in changes if c.benchmark == bench]
        png = _figure_png(bench, ss, commits, bench_changes)
        anchor = series.index(ss[0])
        parts.append(f"<h3 id='b{anchor}'>{esc(bench)}</h3>")
        parts.append(f"<img alt='{esc(bench)}' src='data:image/png;base64,{png}'>")
        for s in ss:
            last = s.points[-1]
            const = {k: v for k, v in last.counters.items()
                     if not any(c.counter == k and c.machine == s.machine
                                for c in bench_changes)}
            text = ", ".join(f"{esc(k)}={_format_count(v)}" for k, v in sorted(const.items()))
            parts.append(f"<p><b>{esc(s.machine)}</b>: {len(s.points)} commits, last "
                         f"median {esc(format_time(last.median))}"
                         + (f"; unchanged exact counters: {text}" if text else "") + "</p>")
    parts.append("<h2>Commits</h2>")
    rows = []
    for ci, (sha, date, subject) in enumerate(commits):
        ms = sorted({r.label for r in runs if r.sha == sha})
        rows.append((ci, f"<code>{esc(sha)}</code>", esc(date.isoformat()), esc(subject),
                     esc(", ".join(ms))))
    parts.append(_table(["#", "commit", "date", "subject", "machines"], rows))
    parts.append("</body></html>\n")
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_file(out, "\n".join(parts))  # a symlink's target, a device written through
    return steps, changes
