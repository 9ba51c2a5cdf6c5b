"""Every relative link of README.md, docs/*.md and the studies' READMEs (experiments/) resolves in the repository: markdown
links (with their #anchors) and inline code spans naming a file or folder of the repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), *sorted((ROOT / "experiments").rglob("README.md"))]
_LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)")
_CODE = re.compile(r"`([^`\s]+)`")
_TOP = ("aaeval/", "configs/", "docs/", "scripts/", "tests/", "benchmarks/", ".ci/", "experiments/")


def _prose(text: str) -> str:
    """The page without fenced code blocks (commands there name files yet to be written)."""
    return re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)


def _anchors(page: Path) -> set[str]:
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to hyphens."""
    heads = re.findall(r"^#+\s+(.*)$", _prose(page.read_text()), flags=re.M)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in heads}


def _links(page: Path) -> list[str]:
    text = _prose(page.read_text())
    return [a or b for a, b in _LINK.findall(text)]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_markdown_links_resolve(page):
    for link in _links(page):
        if re.match(r"^[a-z]+:", link):  # http:, https:, mailto: are not the repository's
            continue
        path, _, anchor = link.partition("#")
        target = (page.parent / path).resolve() if path else page
        assert target.exists(), f"{page.name}: link {link!r} points to {target}, which does not exist"
        assert ROOT in target.parents or target == ROOT, f"{page.name}: {link!r} leaves the repository"
        if anchor and target.suffix == ".md":
            assert anchor in _anchors(target), f"{page.name}: no heading #{anchor} in {target.name}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_named_repository_paths_exist(page):
    for span in _CODE.findall(_prose(page.read_text())):
        path = span.split("::", 1)[0].rstrip(".,:;)")  # a pytest node id names its file
        if not path.startswith(_TOP) or any(ch in path for ch in "*<>{}$"):
            continue
        assert (ROOT / path).exists(), f"{page.name}: `{span}` names a path that is not in the repository"


def test_the_checks_see_links():
    # the README links docs/: a parser that found nothing would pass everything above
    assert "docs/scene_format.md" in _links(ROOT / "README.md")
    assert "scene_format.md" in _links(ROOT / "docs" / "shaded_scenes.md")
