"""HTML reports of sweep folders: ``write_report(DIR)`` writes ``DIR/index.html``."""

from aaeval.report.html import write_report

__all__ = ["write_report"]
