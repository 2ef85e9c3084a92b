"""The claims as JSON objects, as ``claims.json`` stores them (:func:`get_claims_json`)."""

import json
import math
import os

import numpy as np

__all__ = ["get_claims_json"]


def claims_json_text(outcomes, context):
    """The text of ``claims.json``: the run's `context` and :func:`get_claims_json` of the
    `outcomes`, their swept ranges those of the context's ``mode`` (default quick)."""
    return json.dumps({"context": context,
                       "claims": get_claims_json(outcomes, context.get("mode", "quick"))},
                      indent=2, default=_jsonable) + "\n"


def get_claims_json(outcomes, mode="quick"):
    """One JSON-ready object per claim.

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome
    mode : {"quick", "full"}, optional
        The sweep mode, to record each claim's swept range.

    Returns
    -------
    objects : list of dict
        ``id``, ``statement``, ``source``, ``expected_exponent``, ``tolerance``,
        ``measured_exponent``, ``interval_low``, ``interval_high``, ``verdict``, ``reason``,
        and the details of the measurement (``null`` where not computed).
    """
    out = []
    for o in outcomes:
        a, c, d = o.assessment, o.claim, o.data
        fit, iv, theta, models = a.fit, a.interval, a.theta, a.models
        obj = {
            "id": c.id,
            "statement": c.statement,
            "source": c.source,
            "source_key": c.source_key,
            "description": c.description,
            "expected_exponent": c.expected_exponent,
            "tolerance": c.tolerance,
            "measured_exponent": fit.exponent if fit else None,
            "interval_low": iv.low if iv else None,
            "interval_high": iv.high if iv else None,
            "interval_parts": ({
                "statistical": {"low": fit.low, "high": fit.high,
                                "confidence": fit.confidence},
                "window_octaves": iv.window_octaves,
                "window_exponents": iv.windows.slope.tolist(),
                "upper_windows_exponent": None if math.isnan(iv.upper) else iv.upper,
                "drift": iv.drift,
            } if iv else None),
            "verdict": a.verdict,
            "reason": a.reason,
            "expected_to_hold": c.expected_to_hold,
            "as_expected": o.agrees,
            "published": c.published,
            "kind": c.kind,
            "source_words": c.words or None,
            "source_words_at": c.words_at or None,
            "quantity": c.quantity or None,
            "interval_note": c.interval_note or None,
            "alternatives": [{"exponent": alt.exponent, "tilted_verdict": alt.verdict,
                              "tilted_interval": [alt.low, alt.high],
                              "refuted_by_interval": bool(iv and not iv.low <= alt.exponent
                                                          <= iv.high)}
                             for alt in a.alternatives],
            "exact_power_law": a.exact,
            "can_fail": a.can_fail,
            "alternatives_text": a.refutes_text or None,
            "command": c.command,
            "scene": c.scene,
            "mesh": ({"file": os.path.basename(c.mesh), "sha256": c.mesh_sha256}
                     if c.mesh else None),
            "params": c.params,
            "oracle": c.oracle,
            "options": c.options_for(o.mode),
            "eps": c.eps,
            "sweep_param": c.sweep_param,
            "sweep": {"param": c.sweep_param, "from": c.range_for(mode).start,
                      "to": c.range_for(mode).stop,
                      "per_decade": c.range_for(mode).per_decade,
                      "grid": {name: list(values) for name, values in c.grid.items()}},
            "min_area": c.min_area,
            "x": c.x.text,
            "y": c.y.text,
            "regime": {"x_min": c.x_min, "x_max": c.x_max},
            "points": int(a.x.size),
            "points_in_regime": a.n_regime,
            "decades_in_regime": a.decades,
            "failed_points": d.failures,
            "missing_points": d.missing,
            "prefactor": fit.prefactor if fit else None,
            "rms_log10": fit.rms if fit else None,
            "bootstrap": ({"method": "moving-block residual bootstrap", "block": fit.block,
                           "resamples": fit.n_boot, "seed": fit.seed} if fit else None),
            "settled": a.settled,
            "settle_spread": None if math.isnan(a.settle_spread) else a.settle_spread,
            "theta_band": theta.band if theta else None,
            "theta_band_limit": theta.max_band if theta else None,
            "theta_trend_per_decade": theta.trend if theta else None,
            "theta_holds": theta.holds if theta else None,
            "best_model": models.best if models else None,
            "models": ([{"model": n, "delta_aic": float(da), "rms_log10": float(r)}
                        for n, da, r in zip(models.names, models.delta_aic, models.rms,
                                            strict=True)]
                       if models else None),
            "data": {"x": a.x.tolist(), "y": a.y.tolist()},
        }
        out.append(obj)
    return out


def _jsonable(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")
