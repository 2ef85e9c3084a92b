"""What an engine offers, as named results (:class:`Capabilities`), read from
``hrbench capabilities --json``.

Every other module learns what an engine offers from :class:`Capabilities`; none
parses help text or keeps its own list of oracle or counter names. The format of
``capabilities --json`` (capabilities ``schema_version`` 1) is the engine's contract;
the counting conventions behind the counters are in ``docs/conventions.md``.
"""

import math
from dataclasses import dataclass

from ..errors import parse_json
from .process import EngineError

#: Version of the ``capabilities --json`` format that this module reads.
CAPABILITIES_SCHEMA_VERSION = 1

#: Kinds of counter in the capabilities' ``counters`` table: a ``"scalar"`` is one
#: integer, a ``"histogram"`` a list of integers indexed by depth.
COUNTER_KINDS = ("scalar", "histogram")


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
    excludes : tuple of str or None
        The options it cannot be given with, whatever their values (the relation is
        symmetric; the engine lists a pair on one of the two: :meth:`Capabilities.excluded`);
        ``None`` where the engine does not say (an engine before the key ``excludes``).
    """

    name: str
    flag: str
    value: object
    choices: object
    commands: tuple
    doc: str
    excludes: object = None

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

    def excluded(self, name):
        """The options that cannot be given with the option `name`, listed on either side.

        Returns
        -------
        names : frozenset of str or None
            ``None`` if the engine lacks the option or does not say what it excludes (its
            entry has no ``excludes``).
        """
        option = self.option(name)
        if option is None or option.excludes is None:
            return None
        return frozenset(option.excludes) | {
            o.name for o in self.options if name in (o.excludes or ())}

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
                  doc=_value_iv(obj, "doc", "a string", where),
                  excludes=(_strings_iv(obj, "excludes", where) if "excludes" in obj
                            else None))


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
