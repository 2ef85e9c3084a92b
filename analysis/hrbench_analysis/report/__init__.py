"""The report: claims table, per-claim details, figures, as Markdown, HTML and JSON.

Modules
-------
outcome        a claim with its measured points and assessment (:class:`ClaimOutcome`)
table          the claims table: its rows, and its plain text for the terminal
claims_json    the claims as JSON objects (``claims.json``)
figure         a figure of the report (:class:`ReportFigure`), rendered to PNG
charts         the figures drawn from the outcomes (:func:`get_figures`)
sections       what both pages share: columns, contents, anchors, a claim's section
markdown_page  the Markdown report (``report.md``)
html_page      the HTML report (``report.html``), figures embedded
write          the report's files written as one set (:func:`write_report`)
"""

from .charts import get_figures
from .claims_json import get_claims_json
from .figure import ReportFigure
from .outcome import ClaimOutcome
from .table import (
    KINDS_NOTE,
    TERMINAL_WIDTH,
    TIMED_NOTE,
    claims_table_lines,
    format_claims_table,
    get_claims_table,
    print_claims_table,
)
from .write import write_report

__all__ = [
    "ClaimOutcome",
    "ReportFigure",
    "get_claims_table",
    "print_claims_table",
    "format_claims_table",
    "claims_table_lines",
    "TERMINAL_WIDTH",
    "TIMED_NOTE",
    "KINDS_NOTE",
    "get_claims_json",
    "get_figures",
    "write_report",
]
