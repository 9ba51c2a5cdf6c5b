"""The overview: mean primary error and failed cells per method and option (rows) and group
(columns), pivoted from the stored ``specs`` summary."""

from __future__ import annotations

import html

import pandas as pd

from aaeval.report.html_tables import Stored
from aaeval.report.page import Page


SPECS = "summaries/specs.parquet"


def overview_section(page: Page) -> str:
    """Mean primary error and failed cells per method AND option (rows) and group (columns):
    the stored ``specs`` summary, pivoted."""
    primary = page.primary
    specs = page.data.summary("specs")
    if specs.empty:
        return ""
    first = specs.drop_duplicates("spec")
    order = sorted(zip(first["method"], first["options"], first["label"]), key=lambda r: page.styles.order(r[0], r[1]))
    labels = list(dict.fromkeys(label for _, _, label in order))
    groups = list(dict.fromkeys(specs["group"]))
    at = {(r.label, r.group): i for i, r in zip(specs.index, specs[["label", "group"]].itertuples())}

    def pivot(value, column: str) -> tuple[pd.DataFrame, pd.DataFrame]:
        shown_cells = {"method and option": labels}
        where = {"method and option": [next(Stored(SPECS, at[(label, g)], "label") for g in groups if (label, g) in at)
                                       for label in labels]}
        for g in groups:
            shown_cells[g] = [value(at[(label, g)]) if (label, g) in at else None for label in labels]
            where[g] = [Stored(SPECS, at[(label, g)], column) if (label, g) in at else None for label in labels]
        return pd.DataFrame(shown_cells), pd.DataFrame(where)

    errors, where_errors = pivot(lambda i: specs.at[i, primary] if primary in specs else None, primary)
    fails, where_fails = pivot(lambda i: specs.at[i, "failed_of_cells"], "failed_of_cells")
    return ("<h2 id='overview'>Overview</h2>"
            f"<p>Mean {html.escape(primary)} against each group's ground truth, per method and option (one row "
            "each: options are never averaged together). An empty cell: the method did not run in that group.</p>"
            + page.table(errors, "overview_error", f"Mean {primary} per method and option and group", where_errors)
            + f"<p>Failed cells / cells per method and option and group. {page.definition_html}</p>"
            + page.table(fails, "overview_failed", "Failed cells per method and option and group", where_fails))
