"""The report in a real browser: Debian's chromium driven by Playwright (the system
executable; no browser is ever downloaded) opens the report from file:// and checks that
nothing errs, every image and link loads, and the viewer flips, zooms, shows error maps and
space-time slices. Screenshots are inspected (and kept in $AAEVAL_SCREENSHOTS if set).

Without chromium or Playwright the test skips, except under CI=true, where it fails.
"""

from __future__ import annotations

import io
import os
import shutil
from pathlib import Path
from urllib.parse import unquote, urlparse

import numpy as np
import pytest

from aaeval.report.names import figure_stem
from tests.helpers.report_util import small_report

# on the worker that builds the small report for test_report.py too (pyproject's --dist loadgroup)
pytestmark = pytest.mark.xdist_group("small_report")

CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--no-first-run", "--disable-sync"]
VIEWPORT = {"width": 1280, "height": 900}


def _require(ok: bool, reason: str) -> None:
    if ok:
        return
    if os.environ.get("CI", "").lower() == "true":
        pytest.fail(f"{reason}; CI=true: the browser test must run (.ci/run installs chromium and playwright)")
    pytest.skip(reason)


def _chromium() -> str | None:
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    return found or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists() else None)


@pytest.fixture(scope="module")
def browser_page(tmp_path_factory):
    executable = _chromium()
    _require(executable is not None, "Debian's chromium is not installed (apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _require(False, "the playwright Python package is not installed (pip install playwright)")
    index = small_report(tmp_path_factory)
    profile = tmp_path_factory.mktemp("chromium-profile")
    with sync_playwright() as p:
        context = p.chromium.launch_persistent_context(str(profile), executable_path=executable, headless=True,
                                                       args=CHROMIUM_ARGS, viewport=VIEWPORT)
        page = context.new_page()
        problems = []
        page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}") if m.type == "error" else None)
        page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
        page.on("requestfailed", lambda r: problems.append(f"failed to load {r.url}"))
        page.goto(index.as_uri())
        page.wait_for_function("[...document.querySelectorAll('.aav')].every(e => e.dataset.ready === '1')",
                               timeout=30_000)
        yield page, index, problems
        context.close()


def _png(data: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))


def _keep(name: str, data: bytes) -> None:
    folder = os.environ.get("AAEVAL_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        (Path(folder) / name).write_bytes(data)


def _canvas(page, n: int = 0) -> str:
    return page.evaluate(f"document.querySelectorAll('.aav canvas')[{n}].toDataURL()")


@pytest.mark.slow
def test_page_loads_without_errors(browser_page):
    page, index, problems = browser_page
    assert problems == []
    images = page.evaluate("[...document.images].map(i => [i.getAttribute('src'), i.complete && i.naturalWidth])")
    assert len(images) >= 8
    assert all(width > 0 for _, width in images), [src for src, width in images if not width]
    groups = page.evaluate("[...document.querySelectorAll('.aav')].map(e => e.dataset.group)")
    assert figure_stem("edges") in groups and page.evaluate("Object.keys(AAV.data).length") == len(groups)
    for href in page.evaluate("[...document.querySelectorAll('a[href]')].map(a => a.href)"):
        url = urlparse(href)
        assert url.scheme == "file", f"a link leaves the report: {href}"
        assert Path(unquote(url.path)).is_file(), f"link does not resolve: {href}"


@pytest.mark.slow
def test_viewer_flips_zooms_and_shows_errors(browser_page):
    page, _, problems = browser_page
    group = figure_stem("edges")
    viewer = page.locator(f".aav[data-group='{group}']")
    viewer.scroll_into_view_if_needed()
    viewer.locator(".aav-help").click()  # make it the viewer that keys go to
    labels = page.evaluate(f"AAV.data['{group}'].scenes[0].panels.map(p => p.label)")

    page.keyboard.press("1")
    assert viewer.get_attribute("data-layout") == "ab" and viewer.get_attribute("data-shown") == labels[1]
    first = _canvas(page)
    page.keyboard.press("0")
    assert viewer.get_attribute("data-shown") == labels[0]
    ground_truth = _canvas(page)
    assert ground_truth != first
    page.keyboard.press("f")  # flip back: the same image as before
    assert viewer.get_attribute("data-shown") == labels[1] and _canvas(page) == first
    _keep("viewer_flipped.png", viewer.screenshot())

    canvas = viewer.locator("canvas").first
    box = canvas.bounding_box()
    page.mouse.move(box["x"] + box["width"] * 0.4, box["y"] + box["height"] * 0.45)
    for _ in range(4):
        page.mouse.wheel(0, -200)
    page.wait_for_function(f"+document.querySelector(\".aav[data-group='{group}']\").dataset.zoom > 2")
    zoomed = _png(canvas.screenshot())
    assert _canvas(page) != first
    # nearest-neighbour pixels: a zoomed image is made of flat blocks (few distinct rows)
    assert len(np.unique(zoomed.reshape(-1, 3), axis=0)) < 0.05 * zoomed.shape[0] * zoomed.shape[1]
    _keep("viewer_zoomed.png", viewer.screenshot())
    assert "linear RGB" in viewer.locator(".aav-readout").inner_text()

    page.keyboard.press("z")
    viewer.locator("select.aav-mode").select_option("abs")
    viewer.locator(".aav-help").click()
    _keep("viewer_error_map.png", viewer.screenshot())
    assert "|error|" in viewer.locator(".aav-info").first.inner_text()
    viewer.locator("select.aav-mode").select_option("flip")
    viewer.locator(".aav-help").click()
    assert "FLIP map" in viewer.locator(".aav-info").first.inner_text()

    viewer.locator("select.aav-mode").select_option("image")
    viewer.locator("select.aav-layout").select_option("grid")
    viewer.locator(".aav-help").click()
    page.keyboard.press("s")
    assert viewer.get_attribute("data-slice") == "1"
    shot = viewer.screenshot()
    _keep("viewer_space_time.png", shot)
    assert problems == []


@pytest.mark.slow
def test_screenshot_is_the_page_not_a_blank(browser_page):
    page, _, _ = browser_page
    page.evaluate("window.scrollTo(0, 0)")
    data = page.screenshot()
    _keep("report_top.png", data)
    image = _png(data)
    assert image.shape == (VIEWPORT["height"], VIEWPORT["width"], 3)
    grey = image.mean(axis=2)
    assert grey.std() > 10 and len(np.unique(image.reshape(-1, 3), axis=0)) > 50
    assert (grey < 128).mean() > 0.01  # text and figures are drawn, not a white page


@pytest.mark.slow
def test_keys_belong_to_the_viewer_under_the_pointer_or_in_focus(browser_page):
    """Space and arrows scroll the page unless a viewer has the pointer or the focus;
    captions carry the full label; Tab reaches every panel and Enter shows it."""
    page, _, problems = browser_page
    group = figure_stem("edges")
    viewer = page.locator(f".aav[data-group='{group}']")
    page.locator("h1").click()  # focus on the page, the pointer over the title, far from any viewer
    page.evaluate("window.scrollTo(0, 0)")
    layouts = page.evaluate("[...document.querySelectorAll('.aav')].map(e => e.dataset.layout + e.dataset.shown)")
    page.keyboard.press("Space")
    page.wait_for_function("window.scrollY > 0")
    page.keyboard.press("ArrowDown")
    assert page.evaluate("[...document.querySelectorAll('.aav')].map(e => e.dataset.layout + e.dataset.shown)") \
        == layouts
    labels = page.evaluate(f"AAV.data['{group}'].scenes[0].panels.map(p => p.label)")
    viewer.locator("select.aav-layout").select_option("grid")
    caps = viewer.locator(".aav-cap")
    for i in range(caps.count()):
        assert caps.nth(i).get_attribute("title") == labels[i]
        assert caps.nth(i).evaluate("e => e.scrollWidth <= e.clientWidth + 1")  # wrapped, never cut
    canvases = viewer.locator("canvas")
    canvases.first.focus()
    reached = {canvases.first.get_attribute("data-panel")}
    for _ in range(len(labels) - 1):
        page.keyboard.press("Tab")
        reached.add(page.evaluate("document.activeElement.dataset.panel"))
    assert reached == {str(i) for i in range(len(labels))}
    page.keyboard.press("Enter")
    assert viewer.get_attribute("data-layout") == "ab" and viewer.get_attribute("data-shown") == labels[-1]
    assert problems == []
