"""The one package that talks to an ``hrbench`` executable.

It finds and checks the executable, reads its version (``hrbench --version``) and its
capabilities (``hrbench capabilities --json``: the scene families, oracles, methods,
options and counters it offers), builds the command lines of runs, and runs the engine:
every engine process of the analysis is started by :func:`run_engine`, in a process group
of its own that is killed when the engine exits, times out, prints too much or the
analysis is interrupted (:func:`ending_engine_runs`). What a claim asks of the engine is
checked against the capabilities in :mod:`hrbench_analysis.claimfile.checks`.

Modules
-------
process       running an engine process (:func:`run_engine`), exit codes, interrupts
capabilities  what an engine offers (:class:`Capabilities`), read from its JSON
locate        finding the engine: its command words, version and capabilities
run_spec      what identifies a run (:class:`RunSpec`): its command lines and cache key
spelling      numbers, options and scenes as the command line spells them
commands      the command lines from loose values (thin wrappers of :class:`RunSpec`)

It uses the standard library only, so that ``tools/`` can use it too.
"""

from .capabilities import (
    CAPABILITIES_SCHEMA_VERSION,
    COUNTER_KINDS,
    MESH_SCENE,
    Capabilities,
    CapabilitiesError,
    Counter,
    Family,
    FfEstimate,
    Named,
    Option,
    Oracle,
    Param,
    parse_capabilities,
)
from .commands import (
    links_argv,
    run_argv,
    run_links,
    save_argv,
    solve_argv,
    sweep_argv,
    write_links,
)
from .locate import (
    engine_argv,
    engine_text,
    engine_version,
    find_engine,
    get_capabilities,
)
from .process import (
    INPUT_ERROR,
    INTERRUPTED,
    LIMIT_REACHED,
    NOT_STARTED,
    OUTPUT_EXCEEDED,
    OUTPUT_LIMIT,
    TIMED_OUT,
    EngineError,
    EngineRun,
    Interrupted,
    ending_engine_runs,
    interrupt_exit_code,
    kill_engine_runs,
    run_engine,
    start_process,
    stop_engine_runs,
)
from .run_spec import RunSpec, SharedRun
from .spelling import format_number, option_argv, option_flag, option_text

__all__ = [
    "CAPABILITIES_SCHEMA_VERSION",
    "COUNTER_KINDS",
    "INPUT_ERROR",
    "MESH_SCENE",
    "LIMIT_REACHED",
    "NOT_STARTED",
    "EngineError",
    "CapabilitiesError",
    "Param",
    "Family",
    "Oracle",
    "FfEstimate",
    "Named",
    "Option",
    "Counter",
    "Capabilities",
    "EngineRun",
    "engine_argv",
    "engine_text",
    "find_engine",
    "engine_version",
    "get_capabilities",
    "parse_capabilities",
    "format_number",
    "option_flag",
    "option_text",
    "option_argv",
    "RunSpec",
    "run_argv",
    "solve_argv",
    "sweep_argv",
    "SharedRun",
    "links_argv",
    "save_argv",
    "run_engine",
    "start_process",
    "run_links",
    "write_links",
    "kill_engine_runs",
    "stop_engine_runs",
    "ending_engine_runs",
    "interrupt_exit_code",
    "Interrupted",
    "OUTPUT_LIMIT",
    "TIMED_OUT",
    "OUTPUT_EXCEEDED",
    "INTERRUPTED",
]
