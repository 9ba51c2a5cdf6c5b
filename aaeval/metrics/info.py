"""What is known about a metric besides its function: name, title, number format,
direction, its mask and what it needs. Importing this loads nothing that computes, so a
reader of a sweep folder (the report) can format and label the stored values; the sweep
stores every registered metric's :class:`MetricInfo` beside its tables
(:func:`aaeval.sweeps.report_files.write_sweep_files`).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

__all__ = ["MetricInfo", "format_value"]


def format_value(value, fmt: str) -> str:
    """A number in ``fmt``; ``n/a`` for None or NaN, ``inf``/``-inf`` for infinities."""
    if value is None:
        return "n/a"
    value = float(value)
    if value != value:
        return "n/a"
    if value in (float("inf"), float("-inf")):
        return "inf" if value > 0 else "-inf"
    return format(value, fmt)


@dataclass(frozen=True)
class MetricInfo:
    """One metric's description (:class:`aaeval.metrics.Metric` adds its function).

    Attributes
    ----------
    name : str
        Stable name, the key of :data:`aaeval.metrics.METRICS` and the column of the results table.
    kind : {"image", "temporal"}
    title : str
        Short column title for tables and axis labels.
    fmt : str
        Python format spec for one value (``".3e"``).
    higher_is_better : bool
    needs : tuple of str
        What it needs to be computed (:data:`aaeval.metrics.registry.NEEDS`).
    mask : str or None
        Name of the mask (:data:`aaeval.metrics.masks.MASKS`) passed as ``mask=``.
    summary : str
        One line for ``aaeval metrics`` and the report.
    target : float or None
        For a signed metric (a bias), the ideal value: closer to it is better, whatever the
        sign; ``higher_is_better`` is then False and means nothing.
    rms : bool
        The metric is the RMS of the per-pixel error over its pixels (its mask, or all):
        the ground truth's noise is then measured on the same pixels with the same
        reduction, and a per-pixel z-test says whether a method agrees with the truth
        (:mod:`aaeval.metrics.agreement`).
    """

    name: str
    kind: str
    title: str
    fmt: str
    higher_is_better: bool
    needs: tuple[str, ...]
    mask: str | None
    summary: str
    target: float | None = None
    rms: bool = False

    @property
    def direction(self) -> str:
        if self.target is not None:
            return f"closer to {self.target:g} is better"
        return "higher is better" if self.higher_is_better else "lower is better"

    def format(self, value) -> str:
        """``value`` in this metric's format; ``n/a`` for NaN or None, ``inf`` spelled out."""
        return format_value(value, self.fmt)

    def to_dict(self) -> dict:
        """The description as plain data (what the sweep stores)."""
        return {f.name: getattr(self, f.name) for f in fields(MetricInfo)}

    @classmethod
    def from_dict(cls, data: dict) -> "MetricInfo":
        """The description stored by :meth:`to_dict` (fields this aaeval lacks are ignored)."""
        known = {f.name for f in fields(MetricInfo)}
        values = {k: v for k, v in data.items() if k in known}
        values["needs"] = tuple(values.get("needs", ()))
        return cls(**values)


