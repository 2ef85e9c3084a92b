"""The one module that talks to an ``hrbench`` executable.

It finds and checks the executable, reads its version (``hrbench --version``) and its
capabilities (``hrbench capabilities --json``: the scene families, oracles, methods,
options and counters it offers), builds the command lines of runs, checks a claim
against the capabilities before any run starts, and runs the engine: every engine
process of the analysis is started by :func:`run_engine`, in a process group of its
own that is killed when the engine exits, times out, prints too much or the analysis
is interrupted (:func:`ending_engine_runs`).

Every other module learns what an engine offers from :class:`Capabilities`; none
parses help text or keeps its own list of oracle or counter names. The format of
``capabilities --json`` (capabilities ``schema_version`` 1) is the engine's contract;
the counting conventions behind the counters are in ``docs/conventions.md``.

Exit codes of the engine (README.md): 0 success, 1 internal error, 2 usage or input
error (:data:`INPUT_ERROR`), 3 a limit reached during refinement (:data:`LIMIT_REACHED`).
A run that could not be started has exit code 127 (:data:`NOT_STARTED`).

This module uses the standard library only, so that ``tools/`` can use it too.
"""

import math
import os
import selectors
import shlex
import shutil
import signal
import subprocess
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass

from .errors import AnalysisError, parse_json

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
    "oracle_error",
    "resolve_oracle",
    "DEFAULT_ORACLE",
    "KIND_PREFIX",
    "REFERENCE_ORACLES",
    "param_errors",
    "param_range_text",
    "missing_capability",
    "format_number",
    "option_flag",
    "option_text",
    "option_argv",
    "run_argv",
    "solve_argv",
    "links_argv",
    "save_argv",
    "STATISTICS_COMMANDS",
    "run_engine",
    "run_links",
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

#: Version of the ``capabilities --json`` format that this module reads.
CAPABILITIES_SCHEMA_VERSION = 1

#: Kinds of counter in the capabilities' ``counters`` table: a ``"scalar"`` is one
#: integer, a ``"histogram"`` a list of integers indexed by depth.
COUNTER_KINDS = ("scalar", "histogram")

#: Exit code of an engine run refused as a usage or input error (bad parameter value,
#: touching patches without a recursion limit, ...): the analysis exits with 2 as well.
INPUT_ERROR = 2
#: Exit code of an engine run that reached a limit during refinement (the safety depth,
#: the memory budget): a failed point of the sweep, left out of the fit.
LIMIT_REACHED = 3
#: Exit code of :func:`run_engine` for a process that could not be started.
NOT_STARTED = 127


class EngineError(AnalysisError, RuntimeError):
    """The engine cannot be used: missing, not executable, or a command of it failed."""


class CapabilitiesError(EngineError):
    """The engine has no ``capabilities --json`` command, or its output is not readable."""


# ---------------------------------------------------------------------------------------
# The capabilities, as named results.


@dataclass(frozen=True)
class Param:
    """One parameter of a scene family.

    Attributes
    ----------
    name : str
        As on the command line (``l=64``).
    default : float or None
        Default value (the family's unit), or ``None`` when `default_from` is set.
    default_from : str or None
        Name of the parameter whose value is the default (e.g. ``l2`` defaults to ``l``).
    low, high : float or None
        Bounds of the valid range (``None``: unbounded on that side).
    low_open, high_open : bool
        Whether the bound itself is excluded.
    integer : bool
        Whether only integers are valid.
    doc : str
        One line for a reader.
    """

    name: str
    default: object
    default_from: object
    low: object
    high: object
    low_open: bool
    high_open: bool
    integer: bool
    doc: str


@dataclass(frozen=True)
class Family:
    """A scene family of ``hrbench run``.

    Attributes
    ----------
    name : str
        E.g. ``"parallel"``.
    dimension : int
        2 or 3 (dimension of the scene's space).
    doc : str
        One line for a reader.
    params : tuple of Param
        In the engine's order.
    """

    name: str
    dimension: int
    doc: str
    params: tuple

    @property
    def param_names(self):
        """tuple of str: the names of `params`, in order."""
        return tuple(p.name for p in self.params)


@dataclass(frozen=True)
class Oracle:
    """A refinement oracle (``--oracle NAME``).

    Attributes
    ----------
    name : str
    dimensions : tuple of int
        Dimensions of the scenes it works on, e.g. ``(2, 3)``.
    parameters : tuple of str
        Options it reads, e.g. ``("eps",)``.
    doc : str
    kind : str or None
        What it bounds (optional in the listing): ``"geometric"`` (a size over a
        distance), ``"form-factor"`` (an estimate of the form factor), ``"radiosity"``
        (a form factor weighted by radiosity), or another word of the engine's.
    default : bool
        Whether the engine uses it when ``--oracle`` is not given (optional, false).
    """

    name: str
    dimensions: tuple
    parameters: tuple
    doc: str
    kind: object = None
    default: bool = False


@dataclass(frozen=True)
class FfEstimate:
    """A form-factor estimate of the oracles that read one (``--ff-estimate NAME``).

    Attributes
    ----------
    name : str
        E.g. ``"clamped-cosine"``.
    formula_2d, formula_3d : str
        The estimate F(i<-j) in 2D and 3D, in the notation of ``docs/conventions.md``.
    source : str
        Where it comes from, and what of the source was verified.
    oracles : tuple of str
        The oracles that read it, e.g. ``("hanrahan", "bf")``.
    default : bool
        Whether a run without ``--ff-estimate`` uses it.
    """

    name: str
    formula_2d: str
    formula_3d: str
    source: str
    oracles: tuple
    default: bool


@dataclass(frozen=True)
class Named:
    """An entry of the engine that is only a name and a line of doc: a command (``run``,
    ``links``, ...) or a counting method (``--method NAME``).

    Attributes
    ----------
    name : str
    doc : str
    """

    name: str
    doc: str


@dataclass(frozen=True)
class Option:
    """A command-line option of the engine.

    Attributes
    ----------
    name : str
        With underscores, as claims files write option names (``"rays_per_side"``).
    flag : str
        As on the command line (``"--rays-per-side"``).
    value : str or None
        Metavariable of the value, or ``None`` for a switch (``--json``).
    choices : tuple of str or None
        The allowed values, when the option takes one of a fixed set.
    commands : tuple of str
        The commands that accept it.
    doc : str
    """

    name: str
    flag: str
    value: object
    choices: object
    commands: tuple
    doc: str

    @property
    def is_switch(self):
        """bool: whether the option takes no value."""
        return self.value is None


@dataclass(frozen=True)
class Counter:
    """A counter of ``hrbench run --json`` records (a top-level key of the record).

    Attributes
    ----------
    name : str
        E.g. ``"links"``.
    kind : {"scalar", "histogram"}
        One integer, or a list of integers indexed by depth.
    category : str
        Group, e.g. ``"tree"``.
    unit : str
        E.g. ``"elements"``.
    doc : str
    """

    name: str
    kind: str
    category: str
    unit: str
    doc: str


@dataclass(frozen=True)
class Capabilities:
    """What an engine offers, as listed by ``hrbench capabilities --json``.

    Attributes
    ----------
    schema_version : int
        Version of the capabilities format (:data:`CAPABILITIES_SCHEMA_VERSION`).
    engine : str
        Engine name, e.g. ``"hrbench"``.
    version : str
        Engine version, e.g. ``"0.3.0"``.
    run_schema_version : int
        ``schema_version`` of the engine's ``run --json`` records.
    commands : tuple of Named
    families : tuple of Family
    oracles : tuple of Oracle
    methods : tuple of Named
    options : tuple of Option
    counters : tuple of Counter
        Every table in the engine's order. The names of the scalar counters and of the
        histograms are :attr:`scalar_counters` and :attr:`histogram_counters`.
    ff_estimates : tuple of FfEstimate
        The form-factor estimates (``--ff-estimate``), in the engine's order; empty for an
        engine that lists none (the key ``ff_estimates`` is optional).
    """

    schema_version: int
    engine: str
    version: str
    run_schema_version: int
    commands: tuple
    families: tuple
    oracles: tuple
    methods: tuple
    options: tuple
    counters: tuple
    ff_estimates: tuple = ()

    @property
    def scalar_counters(self):
        """tuple of str: names of the counters of kind ``"scalar"``, in order."""
        return tuple(c.name for c in self.counters if c.kind == "scalar")

    @property
    def histogram_counters(self):
        """tuple of str: names of the counters of kind ``"histogram"``, in order."""
        return tuple(c.name for c in self.counters if c.kind == "histogram")

    @property
    def command_names(self):
        """tuple of str: names of the commands, in order."""
        return tuple(c.name for c in self.commands)

    @property
    def family_names(self):
        """tuple of str: names of the scene families, in order."""
        return tuple(f.name for f in self.families)

    @property
    def oracle_names(self):
        """tuple of str: names of the oracles, in order."""
        return tuple(o.name for o in self.oracles)

    @property
    def method_names(self):
        """tuple of str: names of the methods, in order."""
        return tuple(m.name for m in self.methods)

    def family(self, name):
        """The scene family `name`, or ``None`` if the engine lacks it.

        :data:`MESH_SCENE` stands for a mesh file (``--mesh F``): a 3D scene without
        parameters, which an engine has if it takes the option ``mesh``.
        """
        if name == MESH_SCENE:
            return MESH_FAMILY if self.option("mesh") is not None else None
        return next((f for f in self.families if f.name == name), None)

    def oracle(self, name):
        """The oracle `name`, or ``None`` if the engine lacks it."""
        return next((o for o in self.oracles if o.name == name), None)

    def option(self, name):
        """The option `name` (underscores, e.g. ``"min_area"``), or ``None``."""
        return next((o for o in self.options if o.name == name), None)

    def ff_estimate(self, name):
        """The form-factor estimate `name`, or ``None`` if the engine lacks it."""
        return next((e for e in self.ff_estimates if e.name == name), None)


# ---------------------------------------------------------------------------------------
# Reading the capabilities.

_KINDS = {
    "a string": lambda v: isinstance(v, str),
    "an integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "a number": lambda v: (isinstance(v, (int, float)) and not isinstance(v, bool)
                           and math.isfinite(v)),
    "true or false": lambda v: isinstance(v, bool),
    "a list": lambda v: isinstance(v, list),
    "an object": lambda v: isinstance(v, dict),
}


def _value_iv(obj, key, kind, where, nullable=False):
    # obj[key], checked to be of `kind` (a key of _KINDS), or None when `nullable`.
    if key not in obj:
        raise CapabilitiesError(f"{where}: missing key {key!r}")
    value = obj[key]
    if value is None and nullable:
        return None
    if not _KINDS[kind](value):
        allowed = kind + (" or null" if nullable else "")
        raise CapabilitiesError(f"{where}.{key} must be {allowed}, got {value!r}")
    return value


def _strings_iv(obj, key, where, nullable=False):
    # A list of strings (or None when `nullable`), as a tuple.
    values = _value_iv(obj, key, "a list", where, nullable)
    if values is None:
        return None
    for n, value in enumerate(values):
        if not isinstance(value, str):
            raise CapabilitiesError(f"{where}.{key}[{n}] must be a string, got {value!r}")
    return tuple(values)


def _table_iv(obj, key, where, read_entry):
    # A list of objects with unique "name"s, each read by read_entry(entry, where).
    entries = _value_iv(obj, key, "a list", where)
    out, seen = [], set()
    for n, entry in enumerate(entries):
        entry_where = f"{where}.{key}[{n}]"
        if not isinstance(entry, dict):
            raise CapabilitiesError(f"{entry_where} must be an object, got {entry!r}")
        item = read_entry(entry, entry_where)
        if item.name in seen:
            raise CapabilitiesError(f"{entry_where}: duplicate name {item.name!r}")
        seen.add(item.name)
        out.append(item)
    return tuple(out)


def _kind_iv(kind, where):
    if kind not in COUNTER_KINDS:
        raise CapabilitiesError(f"{where}.kind must be one of "
                                f"{', '.join(map(repr, COUNTER_KINDS))}, got {kind!r}")
    return kind


def _read_param(obj, where):
    return Param(
        name=_value_iv(obj, "name", "a string", where),
        default=_value_iv(obj, "default", "a number", where, nullable=True),
        default_from=_value_iv(obj, "default_from", "a string", where, nullable=True),
        low=_value_iv(obj, "low", "a number", where, nullable=True),
        high=_value_iv(obj, "high", "a number", where, nullable=True),
        low_open=_value_iv(obj, "low_open", "true or false", where),
        high_open=_value_iv(obj, "high_open", "true or false", where),
        integer=_value_iv(obj, "integer", "true or false", where),
        doc=_value_iv(obj, "doc", "a string", where))


#: The scene name of a claim that loads a mesh file (its key ``mesh``) instead of
#: building a family.
MESH_SCENE = "mesh"
MESH_FAMILY = Family(name=MESH_SCENE, dimension=3, doc="a polygon mesh file (--mesh F)",
                     params=())


def _read_family(obj, where):
    dimension = _value_iv(obj, "dimension", "an integer", where)
    if dimension not in (2, 3):
        raise CapabilitiesError(f"{where}.dimension must be 2 or 3, got {dimension!r}")
    return Family(name=_value_iv(obj, "name", "a string", where), dimension=dimension,
                  doc=_value_iv(obj, "doc", "a string", where),
                  params=_table_iv(obj, "params", where, _read_param))


def _read_oracle(obj, where):
    dimensions = _value_iv(obj, "dimensions", "a list", where)
    if not all(d in (2, 3) and not isinstance(d, bool) for d in dimensions):
        raise CapabilitiesError(f"{where}.dimensions must list 2 and/or 3, got {dimensions!r}")
    kind, default = obj.get("kind"), obj.get("default", False)
    if kind is not None and not (isinstance(kind, str) and kind):
        raise CapabilitiesError(f"{where}.kind must be a non-empty string, got {kind!r}")
    if not isinstance(default, bool):
        raise CapabilitiesError(f"{where}.default must be true or false, got {default!r}")
    return Oracle(name=_value_iv(obj, "name", "a string", where),
                  dimensions=tuple(dimensions),
                  parameters=_strings_iv(obj, "parameters", where),
                  doc=_value_iv(obj, "doc", "a string", where), kind=kind, default=default)


def _read_named(obj, where):
    return Named(name=_value_iv(obj, "name", "a string", where),
                 doc=_value_iv(obj, "doc", "a string", where))


def _read_option(obj, where):
    return Option(name=_value_iv(obj, "name", "a string", where),
                  flag=_value_iv(obj, "flag", "a string", where),
                  value=_value_iv(obj, "value", "a string", where, nullable=True),
                  choices=_strings_iv(obj, "choices", where, nullable=True),
                  commands=_strings_iv(obj, "commands", where),
                  doc=_value_iv(obj, "doc", "a string", where))


def _read_ff_estimate(obj, where):
    return FfEstimate(name=_value_iv(obj, "name", "a string", where),
                      formula_2d=_value_iv(obj, "formula_2d", "a string", where),
                      formula_3d=_value_iv(obj, "formula_3d", "a string", where),
                      source=_value_iv(obj, "source", "a string", where),
                      oracles=_strings_iv(obj, "oracles", where),
                      default=_value_iv(obj, "default", "true or false", where))


def _read_counter(obj, where):
    return Counter(name=_value_iv(obj, "name", "a string", where),
                   kind=_kind_iv(_value_iv(obj, "kind", "a string", where), where),
                   category=_value_iv(obj, "category", "a string", where),
                   unit=_value_iv(obj, "unit", "a string", where),
                   doc=_value_iv(obj, "doc", "a string", where))


def parse_capabilities(text, engine="hrbench"):
    """Parse the output of ``hrbench capabilities --json``.

    Parameters
    ----------
    text : str
        The standard output of the command.
    engine : str, optional
        The engine's path or name, for the error messages.

    Returns
    -------
    capabilities : Capabilities

    Raises
    ------
    CapabilitiesError
        If the text is not a JSON object, its ``schema_version`` is not
        :data:`CAPABILITIES_SCHEMA_VERSION`, or a key of the format is missing or of the
        wrong type. The message is one line naming the engine and the key. Keys the format
        does not define are ignored (a later engine may add some); ``ff_estimates`` is
        optional (an engine that lists none has no ``--ff-estimate``).
    """
    obj = parse_json(text, f"engine {engine}: the output of 'capabilities --json'",
                     CapabilitiesError)
    if not isinstance(obj, dict):
        raise CapabilitiesError(f"engine {engine}: 'capabilities --json' did not print a "
                                "JSON object")
    try:
        schema = obj.get("schema_version")
        if schema != CAPABILITIES_SCHEMA_VERSION:
            raise CapabilitiesError(f"capabilities has schema_version {schema!r}; this "
                                    f"analysis reads {CAPABILITIES_SCHEMA_VERSION}")
        where = "capabilities"
        return Capabilities(
            schema_version=schema,
            engine=_value_iv(obj, "engine", "a string", where),
            version=_value_iv(obj, "version", "a string", where),
            run_schema_version=_value_iv(obj, "run_schema_version", "an integer", where),
            commands=_table_iv(obj, "commands", where, _read_named),
            families=_table_iv(obj, "families", where, _read_family),
            oracles=_table_iv(obj, "oracles", where, _read_oracle),
            methods=_table_iv(obj, "methods", where, _read_named),
            options=_table_iv(obj, "options", where, _read_option),
            counters=_table_iv(obj, "counters", where, _read_counter),
            ff_estimates=(_table_iv(obj, "ff_estimates", where, _read_ff_estimate)
                          if "ff_estimates" in obj else ()))
    except CapabilitiesError as exc:
        raise CapabilitiesError(f"engine {engine}: {exc}") from None


# ---------------------------------------------------------------------------------------
# Finding the engine, its version and its capabilities.


def engine_argv(hrbench):
    """The words that start every command line of an engine.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The path of an executable (one word, never split), or a command of several words,
        e.g. ``("python3", "examples/external_engine/engine.py")``.

    Returns
    -------
    words : list of str

    Raises
    ------
    EngineError
        If `hrbench` is an empty sequence.
    """
    if isinstance(hrbench, (str, os.PathLike)):
        return [os.fspath(hrbench)]
    words = [os.fspath(word) for word in hrbench]
    if not words:
        raise EngineError("the engine command is empty")
    return words


def engine_text(hrbench):
    """The engine command as one line of shell text, for messages and reports."""
    return shlex.join(engine_argv(hrbench))


def find_engine(hrbench):
    """Check that an engine can be started: its program exists and may be run.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        As in :func:`engine_argv`. A program named with a ``/`` is a path (relative to
        the current directory); one without is looked up on the ``PATH``.

    Returns
    -------
    words : list of str
        :func:`engine_argv` of `hrbench`.

    Raises
    ------
    EngineError
        If the program is not an executable file, or not on the ``PATH``.
    """
    words = engine_argv(hrbench)
    program = words[0]
    if os.sep in program or (os.altsep and os.altsep in program):
        found = os.path.isfile(program) and os.access(program, os.X_OK)
    else:
        found = shutil.which(program) is not None
    if not found:
        raise EngineError(f"engine not found or not executable: {program} "
                          "(build it first, or pass --engine CMD)")
    return words


def engine_version(hrbench):
    """The version string of an engine: the first line of ``hrbench --version``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).

    Returns
    -------
    version : str
        E.g. ``"hrbench 0.3.0"`` (part of every cache key).

    Raises
    ------
    EngineError
        If the executable is missing or ``--version`` fails.
    """
    words = find_engine(hrbench)
    run = run_engine([*words, "--version"], timeout=60)
    lines = run.stdout.strip().splitlines()
    if run.exit_code != 0 or not lines:
        raise EngineError(f"{shlex.join(words)} --version failed with exit code "
                          f"{run.exit_code}"
                          + (f": {run.message}" if run.message else ""))
    return lines[0].strip()


def get_capabilities(hrbench, timeout=60):
    """What an engine offers, from ``hrbench capabilities --json``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    timeout : float, optional
        Seconds to wait for the command.

    Returns
    -------
    capabilities : Capabilities

    Raises
    ------
    EngineError
        If the executable is missing.
    CapabilitiesError
        If the engine has no ``capabilities`` command (it exits non-zero) or prints
        something else than the format. The message is one line naming the engine; the
        analysis then exits with code 2.
    """
    words = find_engine(hrbench)
    path = shlex.join(words)
    run = run_engine([*words, "capabilities", "--json"], timeout=timeout)
    if run.exit_code != 0:
        raise CapabilitiesError(
            f"engine {path} has no usable 'capabilities --json' command (exit code "
            f"{run.exit_code}: {run.message or 'no message'}); this analysis needs an engine "
            f"that lists its capabilities (schema_version {CAPABILITIES_SCHEMA_VERSION})")
    return parse_capabilities(run.stdout, engine=path)


# ---------------------------------------------------------------------------------------
# Checking a claim against the capabilities.


#: How a claim names its oracle through the engine's capabilities instead of by name
#: (its key ``oracle``): ``"@default"``, and ``{ kind = "form-factor" }`` kept as
#: ``"@kind=form-factor"`` until :func:`resolve_oracle` names it.
DEFAULT_ORACLE = "@default"
KIND_PREFIX = "@kind="

#: The kinds and the default of the reference engine's oracles, for an ``hrbench`` whose
#: listing names none (the listing's ``kind`` and ``default`` take precedence).
REFERENCE_ORACLES = {"garmann": "geometric", "hanrahan": "form-factor", "bf": "radiosity"}
REFERENCE_DEFAULT = "garmann"


def resolve_oracle(claim, capabilities):
    """The oracle a claim's selector names on this engine.

    A claim names its oracle by name (``oracle = "hanrahan"``), or through the engine's
    capabilities: ``oracle = "@default"`` (the oracle listed with ``default = true``)
    or ``oracle = { kind = "form-factor" }`` (the one oracle listed with that ``kind``
    for the claim's dimension). An ``hrbench`` that lists no kinds or default gets
    :data:`REFERENCE_ORACLES` and :data:`REFERENCE_DEFAULT`.

    Parameters
    ----------
    claim : Claim
    capabilities : Capabilities

    Returns
    -------
    name : str or None
        The oracle's name (the claim's own for a plain name).
    error : str or None
        Why the selector does not resolve: no oracle, or several, of that kind or marked
        default, with the engine's oracles and their kinds.
    """
    wanted = claim.oracle
    if wanted != DEFAULT_ORACLE and not wanted.startswith(KIND_PREFIX):
        return wanted, None
    reference = capabilities.engine == "hrbench"
    listed_kinds = any(o.kind is not None for o in capabilities.oracles)
    listed_default = any(o.default for o in capabilities.oracles)

    def kind(o):
        if o.kind is None and reference and not listed_kinds:
            return REFERENCE_ORACLES.get(o.name)
        return o.kind

    def default(o):
        if reference and not listed_default:
            return o.name == REFERENCE_DEFAULT
        return o.default

    family = capabilities.family(claim.scene)
    dimension = family.dimension if family is not None else None
    usable = [o for o in capabilities.oracles if dimension is None or dimension in o.dimensions]
    if wanted == DEFAULT_ORACLE:
        found, what = [o for o in capabilities.oracles if default(o)], "marked default"
    else:
        wanted_kind = wanted[len(KIND_PREFIX):]
        found = [o for o in usable if kind(o) == wanted_kind]
        what = f"of kind {wanted_kind!r}" + (f" for {dimension}D" if dimension else "")
    if len(found) == 1:
        return found[0].name, None
    listing = ", ".join(f"{o.name} ({kind(o) or 'no kind'})" for o in capabilities.oracles)
    if not found:
        return None, f"the engine lists no oracle {what}; its oracles: {listing or 'none'}"
    return None, (f"the engine lists several oracles {what} "
                  f"({', '.join(o.name for o in found)}); name one: oracle = "
                  f"\"{found[0].name}\"")


def oracle_error(claim, capabilities):
    """Why a claim can never run on this engine, or ``None``: an oracle it does not list,
    or an option that only other oracles read.

    An oracle name the engine does not list can only be a typo or a claim written for
    another engine, so it is an error (the analysis exits with code 2 before any run),
    unlike a scene family or an option the engine lacks (see :func:`missing_capability`).
    So is an option (in either mode) that the engine lists among the ``parameters`` of
    some oracles but not of the claim's, such as ``ff_estimate`` with ``garmann``: the
    engine refuses every such run.

    Parameters
    ----------
    claim : Claim
        Reads ``claim.oracle`` and ``claim.options_for(mode)``.
    capabilities : Capabilities

    Returns
    -------
    message : str or None
        E.g. ``"oracle 'bf' is not offered by the engine; its oracles: garmann, hanrahan"``
        or ``"option ff_estimate is read by the oracles hanrahan, bf only, not by
        'garmann'"``.
    """
    oracle = capabilities.oracle(claim.oracle)
    if oracle is None:
        return (f"oracle {claim.oracle!r} is not offered by the engine; its oracles: "
                f"{', '.join(capabilities.oracle_names) or 'none'}")
    for mode in ("quick", "full"):
        for name in claim.options_for(mode):
            readers = [o.name for o in capabilities.oracles if name in o.parameters]
            if readers and name not in oracle.parameters:
                return (f"option {name} is read by the oracles {', '.join(readers)} only, "
                        f"not by {claim.oracle!r}")
    return None


def param_range_text(param):
    """The valid range of a scene parameter, in words.

    Parameters
    ----------
    param : Param

    Returns
    -------
    text : str
        E.g. ``"d > 0"``, ``"0 < angle < 180"``, ``"3 <= n <= 100000, an integer"`` or
        ``"any number"``.
    """
    low = None if param.low is None else format_number(param.low)
    high = None if param.high is None else format_number(param.high)
    below = "<" if param.low_open else "<="
    above = "<" if param.high_open else "<="
    if low is not None and high is not None:
        text = f"{low} {below} {param.name} {above} {high}"
    elif low is not None:
        text = f"{param.name} {'>' if param.low_open else '>='} {low}"
    elif high is not None:
        text = f"{param.name} {above} {high}"
    else:
        text = "any number"
    if param.integer:
        text = "an integer" if text == "any number" else f"{text}, an integer"
    return text


def _in_range(param, value):
    # Whether `value` lies in the declared range of `param`.
    if not math.isfinite(value):
        return False
    if param.integer and value != int(value):
        return False
    if param.low is not None and (value < param.low or (param.low_open and value == param.low)):
        return False
    if param.high is not None and (value > param.high
                                   or (param.high_open and value == param.high)):
        return False
    return True


def param_errors(claim, capabilities, modes=("quick", "full")):
    """Why a claim's scene parameters can never run on this engine: the problems found.

    Checked before any run, for a claim whose scene family the engine has (a family it
    lacks is a reason to skip, :func:`missing_capability`): every parameter in
    ``claim.params`` must be one of the family's, and its value, and every value the
    sweep gives the swept parameter in each of `modes`, must lie in the family's declared
    range (``low``, ``high``, ``low_open``, ``high_open``, ``integer`` of
    ``capabilities --json``). Such a claim would only collect runs refused with exit
    code 2, so it is an error (the analysis exits with code 2), not a skip. So is a claim
    whose formulas read hierarchy statistics (``claim.statistics``, see
    :mod:`hrbench_analysis.lemmas`) that cannot be measured for it: on a 3D scene, or with an
    option ``hrbench links`` does not take (``--method translation``).

    Parameters
    ----------
    claim : Claim
        Reads ``scene``, ``params``, ``grid``, ``sweep_param``, ``range_for(mode)``, ``path``,
        ``id`` and the lines of its keys (``key_line``, ``range_keys``).
    capabilities : Capabilities
    modes : sequence of str, optional
        Whose sweep ranges to check (default both).

    Returns
    -------
    errors : list of str
        One line each, naming the file, the line, the claim, the key, the parameter, the
        value and the range, e.g. ``"x.toml:12: claim 'C9': key 'params.d': scene
        parameter d = -1 is out of range for scene 'parallel': d > 0"``. Empty when all is
        well or the engine lacks the family.
    """
    family = capabilities.family(claim.scene)
    if family is None:
        return []
    params = {p.name: p for p in family.params}

    def where(key):
        return f"{claim.path}:{claim.key_line(key)}: claim {claim.id!r}: key {key!r}"

    errors = _statistics_errors(claim, family, capabilities, modes)
    for name, value in claim.params.items():
        key = f"params.{name}"
        if name not in params:
            errors.append(f"{where(key)}: scene {claim.scene!r} has no parameter {name!r} "
                          f"(its parameters: {', '.join(family.param_names) or 'none'})")
        elif not _in_range(params[name], value):
            errors.append(f"{where(key)}: scene parameter {name} = {format_number(value)} is "
                          f"out of range for scene {claim.scene!r}: "
                          f"{param_range_text(params[name])}")
    for name, values in claim.grid.items():
        if name not in params:
            errors.append(f"{where('sweep.grid')}: scene {claim.scene!r} has no parameter "
                          f"{name!r} (its parameters: {', '.join(family.param_names) or 'none'})")
            continue
        bad = [v for v in values if not _in_range(params[name], v)]
        if bad:
            errors.append(f"{where('sweep.grid')}: scene parameter {name} = "
                          f"{format_number(bad[0])} is out of range for scene "
                          f"{claim.scene!r}: {param_range_text(params[name])}")
    param = params.get(claim.sweep_param)
    if param is None:
        return errors
    seen = set()
    for mode in modes:
        key = claim.range_keys.get(mode, f"sweep.{mode}")
        sweep = claim.range_for(mode)
        if sweep in seen:
            continue
        seen.add(sweep)
        bad = [v for v in sweep.values() if not _in_range(param, v)]
        if bad:
            errors.append(f"{where(key)}: the sweep gives scene parameter {param.name} "
                          f"{len(bad)} value(s) out of range for scene {claim.scene!r}, first "
                          f"{format_number(bad[0])}: {param_range_text(param)}")
    return errors


def missing_capability(claim, mode, capabilities):
    """Why the engine cannot run a claim, or ``None`` if it can.

    A claim that needs something the engine lacks is skipped, not failed: an older
    engine may lack the 3D scenes or the visibility options, and its other claims still
    run. What it may lack: the scene family; the
    oracle for the family's dimension (an oracle listed for 2D scenes only, on a 3D
    family); an option of ``run``; or, for an option with a fixed set of values (such as
    ``method``), the value the claim asks for. An oracle the engine does not list at all
    is an error instead (:func:`oracle_error`), checked first, and so is a scene
    parameter the family lacks or a value out of its range (:func:`param_errors`).

    Parameters
    ----------
    claim : Claim
        Reads ``scene``, ``params``, ``oracle`` and ``options_for(mode)``.
    mode : {"quick", "full"}
        Whose options to check.
    capabilities : Capabilities

    Returns
    -------
    reason : str or None
        E.g. ``"engine lacks scene 'parallel3d'"`` or ``"engine lacks option
        --visibility"``.
    """
    family = capabilities.family(claim.scene)
    if family is None:
        return f"engine lacks scene {claim.scene!r}"
    oracle = capabilities.oracle(claim.oracle)
    if oracle is not None and family.dimension not in oracle.dimensions:
        return (f"engine's oracle {claim.oracle!r} does not work on {family.dimension}D "
                f"scenes such as {claim.scene!r} (dimensions "
                f"{', '.join(map(str, oracle.dimensions))})")
    command = getattr(claim, "command", "run")
    if command not in capabilities.command_names:
        return f"engine lacks the command {command!r}"
    if getattr(claim, "statistics", None):
        lacking = [c for c in STATISTICS_COMMANDS if c not in capabilities.command_names]
        if lacking:
            return (f"engine lacks the command(s) {', '.join(lacking)}, which the hierarchy "
                    f"statistics ({', '.join(sorted(claim.statistics))}) need")
    return _missing_option(claim.options_for(mode), capabilities, command)


#: Engine commands that measuring the hierarchy statistics of a run needs
#: (:mod:`hrbench_analysis.lemmas`): ``save`` for the patches, ``links`` for the link list.
STATISTICS_COMMANDS = ("save", "links")


def _statistics_errors(claim, family, capabilities, modes):
    # Why the hierarchy statistics a claim's formulas read (claim.statistics, see
    # lemmas.py) can never be measured for it: they come from the link list of
    # a 2D scene, made by 'hrbench links' with the options of the claim's runs.
    names = sorted(getattr(claim, "statistics", None) or ())
    if not names:
        return []
    key = "y" if set(names) & set(claim.y.names) else "x"
    what = (f"{claim.path}:{claim.key_line(key)}: claim {claim.id!r}: key {key!r}: "
            f"hierarchy statistic(s) {', '.join(names)}")
    if family.dimension != 2:
        return [f"{what} are measured on the link list of a 2D scene; scene "
                f"{claim.scene!r} is {family.dimension}D"]
    errors = []
    for mode in modes:
        for name, value in claim.options_for(mode).items():
            option = capabilities.option(name)
            if option is None or "links" in option.commands:
                continue  # an option the engine lacks is a reason to skip, not an error
            if name == "method" and option_text(value) == "enumerate":
                continue  # 'links' enumerates
            line = (f"{what} need the link list, which 'hrbench links' does not make with "
                    f"{option_flag(name)} {option_text(value)}")
            if line not in errors:
                errors.append(line)
    return errors


def _missing_option(options, capabilities, command="run"):
    # The first reason an option cannot be passed to `command`, or None.
    lacking = []
    for name in options:
        option = capabilities.option(name)
        if option is None or command not in option.commands:
            lacking.append(option_flag(name))
    if lacking:
        return f"engine lacks option{'s' if len(lacking) > 1 else ''} {', '.join(lacking)}"
    for name, value in options.items():
        option = capabilities.option(name)
        if (value is True) != option.is_switch:
            return (f"engine's option {option_flag(name)} "
                    + ("takes no value" if option.is_switch else "takes a value, not a switch"))
        choices = option.choices
        if choices is not None and option_text(value) not in choices:
            return (f"engine lacks {option_flag(name)} {option_text(value)} (choices: "
                    f"{', '.join(choices)})")
    return None


# ---------------------------------------------------------------------------------------
# Command lines.


def format_number(value):
    """Format a number for the command line.

    Parameters
    ----------
    value : float
        Any finite number (in its parameter's unit).

    Returns
    -------
    text : str
        Up to 10 significant digits, or as many as it takes to give back exactly the same
        double (``repr``).
    """
    value = float(value)
    text = f"{value:.10g}"
    return text if float(text) == value else repr(value)


def option_flag(name):
    """The command-line flag of an option name: ``"rays_per_side"`` -> ``"--rays-per-side"``.

    This is the engine's rule for every option (the ``flag`` of its capabilities).
    """
    return "--" + name.replace("_", "-")


def option_text(value):
    """The command-line form of an option value.

    Parameters
    ----------
    value : str, bool, int or float

    Returns
    -------
    text : str
        A string as it is, an integer exactly, a float as in :func:`format_number`,
        ``True`` (a flag) as ``"true"``.
    """
    if value is True:
        return "true"
    if isinstance(value, str):
        return value
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    return format_number(value)


def _options_iv(options):
    if not isinstance(options, dict):
        raise TypeError(f"options must be a dict of option name to value, got {options!r}")
    for name, value in options.items():
        if value is not True and (isinstance(value, bool)
                                  or not isinstance(value, (str, int, float))):
            raise TypeError(f"options[{name!r}] must be a string, an integer, a float or "
                            f"True (a flag), got {value!r}")
    return options


def _params_iv(params):
    if not isinstance(params, dict):
        raise TypeError(f"params must be a dict of parameter name to number, got {params!r}")
    for name, value in params.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"params[{name!r}] must be a number, got {value!r}")
    return params


def option_argv(options):
    """The command-line form of engine options.

    Parameters
    ----------
    options : dict of str to (str, int, float or True)
        E.g. ``{"rays_per_side": 4, "triangulate": True, "visibility": "fraction"}``.

    Returns
    -------
    argv : list of str
        ``["--rays-per-side", "4", "--triangulate", "--visibility", "fraction"]``: sorted
        by name, flags as in :func:`option_flag`, values as in :func:`option_text`; an
        option whose value is ``True`` is a flag without a value.

    Raises
    ------
    TypeError
        If `options` is not a dict, or a value is not a string, integer or float.
    """
    argv = []
    for name, value in sorted(_options_iv(options).items()):
        argv += [option_flag(name)] if value is True else [option_flag(name), option_text(value)]
    return argv


def _scene_argv(scene, params):
    # ["parallel", "d=1", "l=8"]: parameters sorted by name. A mesh comes as the option
    # `mesh` instead (MESH_SCENE has no parameters).
    if scene == MESH_SCENE:
        return []
    return [scene, *(f"{k}={format_number(v)}" for k, v in sorted(_params_iv(params).items()))]


def run_argv(hrbench, scene, params, eps, oracle, min_area=None, max_depth=None,
             options=None):
    """The command line of one counting run: ``hrbench run ... --count-only --json``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units), written ``name=value`` sorted by name.
    eps : float
        Oracle threshold (dimensionless).
    oracle : str
        Oracle name.
    min_area : float, optional
        ``--min-area`` (scene units).
    max_depth : int, optional
        ``--max-depth`` (levels).
    options : dict of str to (str, int or float), optional
        Further options, as in :func:`option_argv`.

    Returns
    -------
    argv : list of str
        ``[hrbench, "run", scene, params..., "--eps", E, "--oracle", O, [--min-area A],
        [--max-depth D], options..., "--count-only", "--json"]``.
    """
    return (_refine_argv(hrbench, "run", scene, params, eps, oracle, min_area, max_depth,
                         options) + ["--count-only", "--json"])


def solve_argv(hrbench, scene, params, eps, oracle, min_area=None, max_depth=None,
               options=None):
    """The command line of one solve: ``hrbench solve ... --json``.

    Parameters are those of :func:`run_argv`; the options must be ones ``solve`` accepts
    (``emission``, ``reference``, ``tolerance``, ...).

    Returns
    -------
    argv : list of str
        ``[hrbench, "solve", scene, params..., "--eps", E, "--oracle", O, [limits],
        options..., "--json"]``.
    """
    return (_refine_argv(hrbench, "solve", scene, params, eps, oracle, min_area, max_depth,
                         options) + ["--json"])


def links_argv(hrbench, scene, params, eps, out, oracle="garmann", min_area=None,
               max_depth=None, options=None):
    """The command line that writes a link list: ``hrbench links ... --out FILE``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units).
    eps : float
        Oracle threshold (dimensionless).
    out : str or path-like or None
        CSV file to write; ``None`` leaves ``--out FILE`` off (the caller appends it).
    oracle : str, optional
        Oracle name (the claims' default, ``garmann``, by default).
    min_area, max_depth, options : optional
        Recursion limits and further options, as in :func:`run_argv` (the options must
        be ones ``links`` accepts).

    Returns
    -------
    argv : list of str
    """
    argv = _refine_argv(hrbench, "links", scene, params, eps, oracle, min_area, max_depth,
                        options)
    return argv + ([] if out is None else ["--out", os.fspath(out)])


def _refine_argv(hrbench, command, scene, params, eps, oracle, min_area, max_depth,
                 options):
    # The words `run`, `solve` and `links` share: scene, threshold, oracle, limits, options.
    argv = [*engine_argv(hrbench), command, *_scene_argv(scene, params),
            "--eps", format_number(eps), "--oracle", oracle]
    if min_area is not None:
        argv += ["--min-area", format_number(min_area)]
    if max_depth is not None:
        argv += ["--max-depth", str(int(max_depth))]
    return argv + option_argv(options or {})


def save_argv(hrbench, scene, params):
    """The command line that prints a scene's patches as JSON: ``hrbench save SCENE ...``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units).

    Returns
    -------
    argv : list of str
    """
    return [*engine_argv(hrbench), "save", *_scene_argv(scene, params)]


# ---------------------------------------------------------------------------------------
# Running the engine.


#: Bytes of standard output an engine run may print: the largest record the analysis
#: reads (``save`` of a 2D scene of 100,000 patches, ``run --sweep`` over thousands of
#: values) is a few MiB. A run that prints more is ended with its child processes and
#: fails as breaking the engine contract; its output is never read into memory whole.
OUTPUT_LIMIT = 64 * 2**20
#: Bytes of the end of standard error that are kept (the message is its last line).
STDERR_KEPT = 64 * 2**10
#: Seconds to read the pipes of an engine that has exited and whose process group is
#: killed: only a process that left the group can hold them longer, and is not waited for.
DRAIN_SECONDS = 2.0
#: Seconds between two looks at whether the engine has exited, while it prints nothing.
POLL_SECONDS = 0.05

#: Why the analysis ended an engine process (:attr:`EngineRun.stopped`): it ran past
#: its timeout,
TIMED_OUT = "timeout"
#: ... it printed more than :data:`OUTPUT_LIMIT` bytes on standard output,
OUTPUT_EXCEEDED = "output"
#: ... or the analysis was interrupted (SIGINT or SIGTERM).
INTERRUPTED = "interrupt"


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM reached the analysis; every engine run it had started is ended.

    A :class:`KeyboardInterrupt`, so that what ends a command on Ctrl-C ends it on
    SIGTERM as well. :attr:`exit_code` is the shell's code for the signal: 130 for
    SIGINT, 143 for SIGTERM.
    """

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)

    @property
    def exit_code(self):
        """int: ``128 + signum``."""
        return 128 + self.signum


def interrupt_exit_code(exc):
    """The exit code for an interrupt: 128 + the signal (130 for a plain Ctrl-C)."""
    return getattr(exc, "exit_code", 128 + signal.SIGINT)


@dataclass(frozen=True)
class EngineRun:
    """One finished engine process.

    Attributes
    ----------
    argv : tuple of str
        The command line.
    exit_code : int
        Exit code (negative for a signal; 127 when it could not be started).
    stdout, stderr : str
        What it printed: standard output up to :data:`OUTPUT_LIMIT` bytes, the last
        :data:`STDERR_KEPT` bytes of standard error.
    wall_seconds : float
        Wall time of the process (s).
    stopped : str
        Why the analysis ended the process: ``""`` (it ended by itself),
        :data:`TIMED_OUT`, :data:`OUTPUT_EXCEEDED` or :data:`INTERRUPTED`.
    reason : str
        One line saying so (``""`` when `stopped` is).
    """

    argv: tuple
    exit_code: int
    stdout: str
    stderr: str
    wall_seconds: float
    stopped: str = ""
    reason: str = ""

    @property
    def message(self):
        """str: why the analysis ended the process, else the last non-empty line of
        standard error ("" if none)."""
        if self.stopped:
            return self.reason
        lines = [line.strip() for line in self.stderr.splitlines() if line.strip()]
        return lines[-1] if lines else ""


# The engine processes of this process that have not been reaped, and whether new ones
# may start. Guarded by _lock (reentrant: the signal handler runs in the main thread,
# which may hold it). A process leaves _live before it is reaped, so that its group id
# is never signalled once it may be reused.
_lock = threading.RLock()
_live = {}  # process -> tag
_stopping = False


def _kill_group(proc):
    # SIGKILL to the engine's process group: the engine and every child it started.
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _exited(proc):
    # Whether the engine has exited, without reaping it: while it is a zombie its pid,
    # and so its group id, cannot be reused, and the group can still be killed safely.
    if hasattr(os, "waitid"):
        try:
            return os.waitid(os.P_PID, proc.pid,
                             os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None
        except ChildProcessError:
            return True
    return proc.poll() is not None


def kill_engine_runs(tag=None):
    """End the engine runs under way in this process, with their children.

    Each :func:`run_engine` ended returns at once with the signal's exit code; later
    calls start their engines as usual. A Dask worker runs it when the sweep it works
    for is interrupted (:mod:`hrbench_analysis.schedulers`).

    Parameters
    ----------
    tag : str, optional
        End only the runs started with this `tag` (those of one sweep, on a worker that
        other sweeps share); default all.

    Returns
    -------
    count : int
        Number of runs ended.
    """
    with _lock:
        ended = [proc for proc, t in _live.items() if tag is None or t == tag]
        for proc in ended:
            _kill_group(proc)
        return len(ended)


def stop_engine_runs():
    """End every engine run of this process, with its children, and start no new one.

    For an interrupt: every :func:`run_engine` under way returns at once (stopped as
    :data:`INTERRUPTED`), and any started later returns without starting its process,
    until :func:`ending_engine_runs` is left.
    """
    global _stopping
    with _lock:
        _stopping = True
        kill_engine_runs()


def _on_signal(signum, frame):
    stop_engine_runs()
    raise Interrupted(signum)


@contextmanager
def ending_engine_runs():
    """The scope of a command that runs engines: SIGINT and SIGTERM end them.

    Inside it (in the main thread), SIGINT and SIGTERM kill the process group of every
    engine run under way (:func:`stop_engine_runs`) and raise :class:`Interrupted` in the
    main thread, whose handlers then wait for nothing: the threads running engines
    return at once. A signal this process ignores (a background job's SIGINT) stays
    ignored. Leaving the scope, by any way, ends what is still running and restores
    the handlers.
    """
    global _stopping
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum in (signal.SIGINT, signal.SIGTERM):
            if signal.getsignal(signum) is not signal.SIG_IGN:
                previous[signum] = signal.signal(signum, _on_signal)
    try:
        yield
    finally:
        stop_engine_runs()
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        with _lock:
            _stopping = False


def _read(proc, timeout):
    # Read both pipes until they close, bounded in time and size; kill the group when
    # the engine exits (its children must not hold the pipes), times out or prints too
    # much. Returns (stdout bytes, stderr bytes, stopped).
    out, err = [], bytearray()
    out_size, stopped, exited_at = 0, "", None
    deadline = None if timeout is None else time.monotonic() + timeout
    with selectors.DefaultSelector() as sel:
        sel.register(proc.stdout, selectors.EVENT_READ)
        sel.register(proc.stderr, selectors.EVENT_READ)
        while sel.get_map():
            now = time.monotonic()
            if exited_at is None and _exited(proc):
                _kill_group(proc)
                exited_at = now
            elif exited_at is not None and now - exited_at > DRAIN_SECONDS:
                break
            if deadline is not None and now > deadline and not stopped:
                stopped = TIMED_OUT
                _kill_group(proc)
            for key, _ in sel.select(POLL_SECONDS):
                data = os.read(key.fd, 65536)
                if not data:
                    sel.unregister(key.fileobj)
                elif key.fileobj is proc.stderr:
                    err += data
                    del err[:-STDERR_KEPT]
                elif not stopped:
                    out_size += len(data)
                    if out_size > OUTPUT_LIMIT:
                        stopped = OUTPUT_EXCEEDED
                        _kill_group(proc)
                    else:
                        out.append(data)
    return b"".join(out), bytes(err), stopped


def run_engine(argv, timeout=None, tag=None):
    """Run the engine once and wait for it: the one place where the analysis starts an
    engine process.

    The process runs in a process group of its own (a new session, without the
    terminal), so that it and every child it starts can be ended together. The group is
    killed when the engine has exited (a child left behind, say one that keeps standard
    output open, is ended, never waited for), when it runs past `timeout`, when it
    prints more than :data:`OUTPUT_LIMIT` bytes on standard output, when this call is
    interrupted (KeyboardInterrupt in the main thread) and on SIGINT or SIGTERM within
    :func:`ending_engine_runs`. No process of the group survives the call.

    Parameters
    ----------
    argv : sequence of str or path-like
        The command line, the engine first.
    timeout : float, optional
        Seconds to let it run (default: no limit).
    tag : str, optional
        Names the run for :func:`kill_engine_runs`.

    Returns
    -------
    run : EngineRun
        A process that could not be started has exit code 127 (:data:`NOT_STARTED`) and
        the reason as its standard error. One the analysis ended has the signal's
        negative exit code, :attr:`EngineRun.stopped` says why and
        :attr:`EngineRun.message` says so in a line. Output that is not UTF-8 is decoded
        with replacement characters.
    """
    argv = tuple(os.fspath(a) for a in argv)
    start = time.perf_counter()

    def finished(code, out, err, stopped="", reason=""):
        return EngineRun(argv, code, out, err, time.perf_counter() - start, stopped, reason)

    proc = None
    try:
        with _lock:
            if _stopping:
                return finished(-signal.SIGKILL, "", "", INTERRUPTED,
                                "not started: the analysis was interrupted")
            try:
                proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, start_new_session=True)
            except (OSError, ValueError) as exc:
                return finished(NOT_STARTED, "", f"cannot run {argv[0]}: {exc}")
            _live[proc] = tag
        out, err, stopped = _read(proc, timeout)
    finally:
        if proc is not None:
            with _lock:
                _live.pop(proc, None)
                if proc.returncode is None:
                    _kill_group(proc)
            proc.stdout.close()
            proc.stderr.close()
            proc.wait()
    with _lock:
        if not stopped and _stopping and proc.returncode < 0:
            stopped = INTERRUPTED
    reasons = {
        TIMED_OUT: f"did not finish within {timeout} s; the analysis ended it and its "
                   "child processes",
        OUTPUT_EXCEEDED: f"printed more than {OUTPUT_LIMIT / 2**20:g} MiB on standard output, "
                         "the most the analysis reads; the analysis ended it",
        INTERRUPTED: "ended: the analysis was interrupted"}
    return finished(proc.returncode, out.decode("utf-8", errors="replace"),
                    err.decode("utf-8", errors="replace"), stopped, reasons.get(stopped, ""))


def run_links(hrbench, scene, params, eps, out, oracle="garmann"):
    """Write the link list of one refinement with ``hrbench links``.

    Parameters are those of :func:`links_argv`.

    Raises
    ------
    EngineError
        If the run fails; the message holds its exit code and last line of standard error.
    """
    run = run_engine(links_argv(hrbench, scene, params, eps, out, oracle))
    if run.exit_code != 0:
        raise EngineError(f"{' '.join(run.argv[1:])} failed with exit code {run.exit_code}: "
                          f"{run.message or 'no message'}")
