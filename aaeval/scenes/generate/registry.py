"""The one registry of scene generators: scenes built from one *difficulty* value, which
sweeps (``generator = "fan"`` in an experiment config) raise to find where each method
starts to fail.

Every generator declares the range of its difficulty and each parameter's type, default
(given once) and range; :func:`generate_scene` checks them all, and the size of what would
be built (:data:`MAX_POLYGONS`, :data:`MAX_PIXEL_FRAMES`), before building anything, and
refuses bad input with a one-line :class:`GeneratorError` naming the generator, the
parameter and the rule.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping

from aaeval.options import Option, Registry
from aaeval.scenes.format import SceneError

__all__ = ["GENERATORS", "Generator", "GeneratorError", "MAX_PIXEL_FRAMES", "MAX_POLYGONS", "generate_scene",
           "register_generator"]


# A generated scene holds at most this many polygons: validating 100k triangles takes
# about 30 s and 0.5 GB on one core, and every method renders each of them per frame.
MAX_POLYGONS = 100_000
# ... and at most this many pixels over all its frames (the scene format's pixel limit).
MAX_PIXEL_FRAMES = 1 << 28


class GeneratorError(SceneError):
    """A generator name, difficulty or parameter that is unknown, of the wrong type or
    out of range, or a scene too large to build; the message is one line."""


@dataclass(frozen=True)
class Generator:
    """A registered generator: ``make(difficulty, **params) -> scene document``.

    ``difficulty`` is what the difficulty value measures (for axis labels);
    ``difficulty_param`` its type and range; ``params`` the other parameters;
    ``size(difficulty, params) -> (polygons, pixels x frames)`` what the scene would hold,
    checked against the limits before ``make`` runs.
    """

    name: str
    make: Callable[..., dict]
    difficulty: str
    difficulty_param: Option
    params: Mapping[str, Option]
    size: Callable[[float, Mapping[str, Any]], tuple[int, int]]


GENERATORS: Registry = Registry("scene generator", GeneratorError)


def register_generator(
    name: str,
    make: Callable[..., dict] | None = None,
    *,
    difficulty: str,
    difficulty_param: Option,
    params: Mapping[str, Option],
    size: Callable[[float, Mapping[str, Any]], tuple[int, int]],
):
    """Register ``make(difficulty, **params) -> scene document`` under ``name``:
    ``register_generator(name, make, ...)`` or ``@register_generator(name, ...)``."""

    def decorate(func):
        GENERATORS.add(name, Generator(name, func, difficulty, difficulty_param, dict(params), size))
        return func

    return decorate if make is None else decorate(make)


def generate_scene(name: str, difficulty: float, **params: Any) -> dict:
    """The scene document generator ``name`` builds at ``difficulty``.

    Every parameter not given takes its declared default. Raises :class:`GeneratorError`
    (one line) for an unknown generator or parameter, a value of the wrong type or out of
    range, or a scene over :data:`MAX_POLYGONS` polygons or :data:`MAX_PIXEL_FRAMES`
    pixels x frames (with the estimate), before building anything.
    """
    gen = GENERATORS.get_entry(name)
    unknown = sorted(set(params) - set(gen.params))
    if unknown:
        raise GeneratorError(f"generator {name!r}: unknown parameter(s) {unknown}; parameters: {sorted(gen.params)}")
    d = gen.difficulty_param.convert(difficulty, f"generator {name!r}: difficulty ({gen.difficulty_param.doc})",
                                    GeneratorError)
    values = {key: p.default for key, p in gen.params.items()}
    for key, value in params.items():
        values[key] = gen.params[key].convert(value, f"generator {name!r}: parameter {key}", GeneratorError)
    polygons, pixel_frames = gen.size(d, values)
    if polygons > MAX_POLYGONS:
        raise GeneratorError(f"generator {name!r} at difficulty {d:g} would build {polygons} polygons; "
                             f"the limit is {MAX_POLYGONS}")
    if pixel_frames > MAX_PIXEL_FRAMES:
        raise GeneratorError(f"generator {name!r} would render {pixel_frames} pixels over all frames; "
                             f"the limit is {MAX_PIXEL_FRAMES}")
    try:
        return gen.make(d, **values)
    except GeneratorError:
        raise
    except (SceneError, ValueError) as exc:  # a combination the builder cannot lay out
        raise GeneratorError(f"generator {name!r} at difficulty {d:g}: {exc}") from None
