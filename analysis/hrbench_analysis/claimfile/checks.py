"""Checking a claim against what the engine offers, before any run starts: the oracle it
selects (:func:`resolve_oracle`), the names its formulas read (:func:`check_names`), its
scene family, parameters, options and statistics (:func:`param_errors`,
:func:`missing_capability`)."""

import math

from ..engine import format_number, option_flag, option_text
from ..lemmas import STATISTICS
from ..loader import environment_names
from .model import DEFAULT_ORACLE, KIND_PREFIX, ClaimsFileError

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


def check_names(claim, counters, scene_params=()):
    """Check that a claim's formulas read only names a run provides.

    A formula may read the scene parameters (the claim's and the family's), ``eps``,
    ``g`` (with ``l`` and ``d``), the engine's scalar counters, the measures
    ``patches`` and ``seconds``, the aliases ``N`` and ``L`` (see
    :func:`hrbench_analysis.loader.run_environment`), and the hierarchy statistics of
    :data:`hrbench_analysis.lemmas.STATISTICS`; a claim with ``command = "solve"`` also
    the solve's measures (:data:`hrbench_analysis.loader.SOLVE_MEASURES`). Any other name
    is a typo: the analysis exits with code 2 before any run.

    Parameters
    ----------
    claim : Claim
    counters : iterable of str
        Names of the engine's scalar counters
        (:attr:`hrbench_analysis.engine.Capabilities.scalar_counters`).
    scene_params : iterable of str, optional
        Parameter names of the claim's scene family (they have defaults, so a run
        reports them even where the claim does not set them).

    Raises
    ------
    ClaimsFileError
        Naming the file, the line, the claim, the key (``x`` or ``y``), the unknown
        names and the known ones.
    """
    known = environment_names({*claim.params, *claim.grid, *scene_params}, counters,
                              solve=claim.command == "solve")
    # The hierarchy statistics (lemmas.py); where they cannot be measured (a 3D
    # scene, --method translation) hrbench_analysis.claimfile.param_errors says so.
    known |= set(STATISTICS)
    formulas = [("x", claim.x), ("y", claim.y)]
    if claim.plateaus is not None:
        formulas.append(("plateaus.of", claim.plateaus.of))
    if claim.alternative is not None:
        formulas.append(("alternative", claim.alternative))
    for key, expr in formulas:
        unknown = expr.names - known
        if unknown:
            raise ClaimsFileError(
                claim.path, f"key {key!r} reads unknown name(s) {', '.join(sorted(unknown))}; "
                f"known: {', '.join(sorted(known))}",
                line=claim.key_line(key), claim_id=claim.id, key=key)
