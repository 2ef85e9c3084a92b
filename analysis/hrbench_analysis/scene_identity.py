"""Scene identity: is the outside engine refining hrbench's patches?

An engine's run record may report ``scene_sha256``, the SHA-256 of the canonical text
of its root patches' corners (docs/scene-format.md#scene-digest). After a sweep, the
analysis compares it, for every scene of a claim (family and parameters, or mesh), with
the digest that hrbench itself reports for that scene (``hrbench save``), and refuses the
claim when they differ: counts of other geometry say nothing about the claim
(docs/engine-contract.md#scene-identity). Without hrbench at hand (``build/hrbench``
under the current directory, or ``hrbench`` on the ``PATH``) the check is skipped with
a warning.
"""

import os
import shutil
from pathlib import Path

from .engine import MESH_SCENE, engine_argv, engine_text, format_number, run_engine
from .engine.spelling import scene_argv
from .errors import one_line
from .loader import ResultFormatError, parse_run_json, read_scene_digest

__all__ = ["reference_engine", "scene_mismatch", "SCENE_OPTIONS"]

#: The claim options that change the patches of a scene (the others change how they are
#: refined): hrbench's ``save`` takes these.
SCENE_OPTIONS = ("mesh", "scale", "triangulate")

#: Seconds that hrbench's ``save`` of one scene may take.
SAVE_TIMEOUT = 600


def reference_engine(engine):
    """hrbench, to compare an engine's scenes with: ``build/hrbench`` under the current
    directory, else ``hrbench`` on the ``PATH``.

    Returns
    -------
    reference : str or None
        Its path; ``None`` when there is none.
    same : bool
        Whether `engine` is that hrbench itself: then there is nothing to compare.
    """
    local = Path("build") / "hrbench"
    found = str(local) if local.exists() else shutil.which("hrbench")
    if found is None:
        return None, False
    words = engine_argv(engine)
    return found, len(words) == 1 and os.path.realpath(words[0]) == os.path.realpath(found)


def _reported(points, store):
    # {params: (set of digests, first point)} of the points whose stored record reports
    # a scene_sha256 (a string); records are the engine's, already read by the sweep.
    seen = {}
    for point in points:
        stored = store.get(point.key)
        if stored is None or not stored.ok:
            continue
        try:
            digest = parse_run_json(stored.output).extra.get("scene_sha256")
        except ResultFormatError:
            continue
        if isinstance(digest, str):
            digests, _ = seen.setdefault(point.key.params, (set(), point))
            digests.add(digest)
    return seen


def _scene_text(claim, params):
    # "parallel d=1 l=8", or "mesh F.obj".
    if claim.scene == MESH_SCENE:
        return f"mesh {claim.mesh}"
    return " ".join(scene_argv(claim.scene, dict(params)))


def scene_mismatch(claim, mode, points, store, reference, digests=None):
    """The error line of a claim whose engine refined other patches than hrbench, or
    ``None``; and the warning lines of checks skipped.

    Parameters
    ----------
    claim : Claim
    mode : {"quick", "full"}
        The mode the points were expanded for (their runs carry its options).
    points : sequence of SweepPoint
        The claim's points, run (:func:`hrbench_analysis.sweep_plan.expand_claim`);
        hrbench saves the scene of each one's run with the options that change its
        patches (:data:`SCENE_OPTIONS`).
    store : ResultStore
    reference : str or None
        hrbench (:func:`reference_engine`); ``None``: nothing to compare with.
    digests : dict, optional
        hrbench's digests by its ``save`` command line, filled and reused across claims.

    Returns
    -------
    error : str or None
        E.g. ``"x.toml:6: claim 'C1': the engine refined other patches than hrbench for
        parallel3d d=1 l=1 ...: scene_sha256 ... (engine) != ... (hrbench build/hrbench)"``.
    warnings : list of str
    """
    reported = _reported(points, store)
    if not reported:
        return None, []
    where = f"{claim.path}:{claim.line}: claim {claim.id!r}"
    if reference is None:
        return None, [f"{where}: the engine reports scene_sha256, but no hrbench "
                      "(build/hrbench, or hrbench on the PATH) is at hand to compare it "
                      "with; the scene is not checked"]
    digests = {} if digests is None else digests
    warnings = []
    for params, (found, point) in reported.items():
        # The point's scene, with the options that change its patches (a mesh among them).
        argv = tuple(point.run.save_argv(reference, SCENE_OPTIONS))
        if argv not in digests:
            run = run_engine(argv, timeout=SAVE_TIMEOUT)
            digest = read_scene_digest(run.stdout) if run.exit_code == 0 else None
            digests[argv] = digest if isinstance(digest, str) else (
                f"exit code {run.exit_code}: {run.message or 'no scene_sha256'}")
        expected = digests[argv]
        scene = _scene_text(claim, params)
        if len(expected) != 64:  # hrbench could not save the scene: say so, judge on
            warnings.append(f"{where}: hrbench cannot give the digest of {scene} "
                            f"({expected}); the scene is not checked")
            continue
        other = sorted(found - {expected})
        if other:
            at = f"{claim.sweep_param}={format_number(point.value)}"
            return one_line(
                f"{where}: the engine refined other patches than hrbench for {scene} "
                f"(first at {at}): scene_sha256 {other[0]} (engine) differs from "
                f"{expected} (hrbench {engine_text(reference)} save); the claim is not "
                "judged on another geometry (docs/engine-contract.md#scene-identity)"), warnings
    return None, warnings
