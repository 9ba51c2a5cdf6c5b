"""A figure's ``alt`` text is its caption as plain text, escaped once:
the caption is HTML (escaped names, links), so escaping it again showed ``&amp;quot;``."""

from __future__ import annotations

import html
from html.parser import HTMLParser
from pathlib import Path


class _Alt(HTMLParser):
    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.alt = dict(attrs)["alt"]


def test_alt_text_is_the_captions_plain_text(tmp_path):
    from aaeval.report.page import figure_html

    name = 'scene "A" & <b>'
    caption = f"Slices of {html.escape(name)}: see <a href='#speed'>Speed</a>."
    page = figure_html(tmp_path / "figures" / "f.png", tmp_path, caption)
    parser = _Alt()
    parser.feed(page)
    assert parser.alt == f"Slices of {name}: see Speed."  # as a browser reads the attribute
