"""What a config may ask for, checked before any work: how many cells it plans, and
whether each render of a cell or of the speed pass fits the time limit of one task.

A config no run would finish is refused when it is read, with its count or estimate, not
stopped half-way through the sweep.
"""

from __future__ import annotations

from aaeval.sweeps.config_keys import ConfigError

__all__ = ["MAX_CELLS", "check_cell_count", "check_speed_budget"]

#: The most cells one config may plan: every cell is a record, a row and a render.
MAX_CELLS = 200_000


def check_cell_count(groups: list, where: str) -> None:
    """Refuse a config of more than :data:`MAX_CELLS` cells, counted before any is built."""
    total = 0
    for g in groups:
        per_spec = sum(src.frames if g.frames == "all" else len(g.frames) for src in g.scenes)
        total += per_spec * len(g.specs)
    if total > MAX_CELLS:
        raise ConfigError(f"{where}: {total} cells (groups x scenes x method specs x frames), over the limit of "
                          f"{MAX_CELLS}; at even 0.1 s a cell that is {total * 0.1 / 3600:.3g} hours (split the "
                          "config or give fewer frames)")


def check_speed_budget(scenes, specs, repeats: int, where: str, limit: float | None, what: str = "speed") -> None:
    """Each render of a cell or the speed pass, with its warm-up and ``repeats`` rounds,
    estimated (the render budget's own estimate) against the time limit of one task: a size
    no run would finish is refused now, with the estimate, not when it is stopped."""
    from aaeval.renderers.budget import check_budget
    from aaeval.renderers.cost import render_seconds
    from aaeval.renderers.registry import MethodError
    from aaeval.sweeps.task_failures import task_limit

    limit_s = task_limit(limit)
    for src in scenes:
        for spec in specs:
            try:  # the render's own budget (samples, memory, time), as `aaeval render` applies it
                check_budget(src.parsed, spec.method, spec.options)
            except MethodError as exc:
                raise ConfigError(f"{where}: {spec}: {exc}") from None
            try:
                seconds = render_seconds(src.parsed, spec.method, spec.options) * (repeats + 1)
            except Exception:  # noqa: BLE001 - a method's own estimate failing: no estimate, the run decides
                continue
            if seconds > limit_s:
                raise ConfigError(f"{where}: {spec} on {src.name} ({src.parsed.width}x{src.parsed.height}) x "
                                  f"{repeats + 1} renders would take about {seconds:.3g} s, over the limit of "
                                  f"{limit_s:g} s (max_seconds or AAEVAL_MAX_SECONDS; a smaller scene or fewer "
                                  "repeats)")
