"""Scenes: the JSON ``hrbench save`` prints: the root patches of a scene, its digest."""

import json

import numpy as np

from .record import ResultFormatError


def read_scene_segments(text, error=None):
    """The root segments of a 2D scene, from ``hrbench save`` (scene JSON).

    Parameters
    ----------
    text : str
        The scene file: ``{"dimension": 2, "patches": [{"a": [x, y], "b": [x, y]}, ...]}``.
    error : type, optional
        The exception raised (default :class:`ResultFormatError`), with one message.

    Returns
    -------
    a, b : ndarray, shape (n, 2)
        Start and end point of every root patch, in scene order (scene units).

    Raises
    ------
    error
        If the text is not such a scene, or the scene is not 2D.
    """
    error = error or ResultFormatError
    try:
        obj = _scene_object(text)
        if obj.get("dimension") != 2:
            raise error(f"hierarchy statistics need a 2D scene; this one has "
                        f"dimension {obj.get('dimension')!r}")
        a = np.array([p["a"] for p in obj["patches"]], dtype=np.float64).reshape(-1, 2)
        b = np.array([p["b"] for p in obj["patches"]], dtype=np.float64).reshape(-1, 2)
    except error:
        raise
    except (ValueError, TypeError, KeyError, AttributeError) as exc:
        raise error(f"unreadable scene from 'hrbench save' ({type(exc).__name__}: "
                    f"{exc})") from None
    return a, b


def read_scene_digest(text):
    """The digest a scene JSON of ``hrbench save`` reports (``scene_sha256``), or ``None``
    when it reports none or the text is not a JSON object."""
    try:
        digest = _scene_object(text).get("scene_sha256")
    except (ValueError, AttributeError):
        return None
    return digest if isinstance(digest, str) else None


def _scene_object(text):
    # The scene JSON as Python objects: the one place it is parsed (ValueError if it is
    # not JSON; the caller checks it is an object).
    return json.loads(text)
