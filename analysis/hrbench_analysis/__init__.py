"""hrbench analysis: sweeps of the hrbench engine, exponent fits and claim verdicts.

Modules
-------
errors      AnalysisError, the base of every error that means bad input (exit code 2)
engine      the one package that runs the engine: version, capabilities, command lines,
            processes
claimfile   read and check the claims files (``analysis/hrbench_analysis/claims/*.toml``),
            and a claim against the engine's capabilities
expr        the safe formula evaluator used for a claim's x and y
loader      read the engine's output (run JSON, link CSV, solution CSV)
store       the SQLite results cache: checked when opened, leases for concurrent sweeps
store_points
            a point of the cache: its key, a cached run, which failures are final
store_leases
            a sweep's lease on a point, and whether its owner still runs
store_schema
            the cache's tables, columns and cell types, its id and layout number
sweep_plan  expand claims into runs
sweep       run the points in parallel, dearest first, and read them back
schedulers  where the runs execute: a local pool, or a Dask cluster
powerlaw    the least-squares power law and its bootstrap interval
slopes      local slopes, window exponents, one point per plateau of a staircase
fit         exponent intervals, Theta checks, models; exports every fitting function
verdict     the verdict of a claim
plots       plotting functions (each draws on a given Axes)
report      the Markdown, HTML and JSON report
output      every output file written whole: a temporary file renamed over it, a
            symlink's target, a device written through; a report set all or none
raster      the camera and the z-buffer rasteriser of a 3D solution's leaves
drawing     render a 3D solution, draw a 2D profile or mplot3d polygons
render      ``hrbench-render``, a solve drawn with mplot3d; exports the drawing
            functions with the camera and the solution reader
solution    the report's pictures of a solve: the profile on the plates, the Cornell box
tiling      ``hrbench-tiling``: the link tilings of a flatland pair at several eps
explorer    the page of sliders over eps and l (``results/explorer.html``, ``hrbench-explorer``)
cli         what the drawing commands share: engine options, scene words, one-line errors
reproduce   the command lines ``hrbench-reproduce`` (``python -m hrbench_analysis.reproduce``)
            and ``hrbench-sweep``
reproduce_options
            their options, and the engine they run when none is named
bench       the benchmark and regression tooling: Google Benchmark files (gbench),
            ``hrbench-compare`` (benchcompare, cmdtiming), a commit built in its git
            worktree (builds, the CI gates), ``hrbench-history`` (history)

An engine other than hrbench works if it keeps the engine contract
(docs/engine-contract.md); its run records are described by
schemas/run-record.schema.json.
"""

__version__ = "0.5.0"
