"""The page's "How to read this report" section: the ground truth, noise, styles, times, units,
controls, the failure definition, the viewer's keys and the files, in words."""

from __future__ import annotations

import html

from aaeval.report import figures
from aaeval.report.page import Page


# Below 256 x 256 pixels a render's time is mostly call overhead: such groups report accuracy.
SPEED_MIN_PIXELS = 256 * 256


def how_to_read_section(page: Page) -> str:
    from aaeval.report.controls_table import controls_html

    return f"""<h2 id='how-to-read'>How to read this report</h2><ul>
<li><b>Ground truth.</b> Every error is measured against the reference named at the top of each group (normally
the Mitsuba high-spp render); its measured noise is stated with it. The section <a href='#ground-truth'>Ground
truth</a> shows that the exact renderers agree with it within that noise.</li>
<li><b>Errors near the noise.</b> Against a noisy ground truth nothing can score below its noise: the grey band in
the charts marks it. An exact method lands on the band; a method above it is wrong by more than the ground truth's
own uncertainty. An error that is zero up to float rounding (below {figures.EXACT_BELOW:g}, possible only against
an exact reference) is drawn on a marked "exact" strip at the bottom of the axis.</li>
<li><b>Styles.</b> A method keeps one colour, marker and dash pattern in every figure; the shades of that colour
(light to dark) and growing markers are its option ladder (k, spp) from smallest to largest; marker fills (full,
empty, half) are categorical options. Legends list methods in one order, options by value.</li>
<li><b>Times.</b> Only the speed pass is timed for the page (section <a href='#speed'>Speed</a>): one worker,
a stated thread count, each method warmed up on its own spec, then interleaved rounds on images of at least
{SPEED_MIN_PIXELS} pixels (256 x 256), as time per megapixel (median, bars from the fastest to the slowest round).
The accuracy cells may run on several workers at once: their times are never charted.</li>
<li><b>Units.</b> {figures.UNIT}. Error maps and grids share one scale per figure (the viewer's "shared scale"
checkbox switches to each panel's own).</li>
<li><b>Bias and flicker.</b> Over an animation a method's error splits into its bias (the time-average of the
error, the part that stays with the object) and its flicker (what is left, frame to frame); for highlights the
same split is made on the highlight's energy, so a clamp that dims the highlight wherever it goes shows as bias,
not as flicker. Each is one registered metric (aaeval/metrics), used by every table, chart and section.</li>
<li id='controls'><b>Controls.</b> Each temporal measure is checked on images whose answer is known before it judges
a method (aaeval/metrics/controls.py; scored by the sweep, for the measures it took):
{controls_html(page.data.controls)}</li>
<li><b>Failed.</b> {html.escape(page.definition)} The same definition is used by every table and chart; a metric
that could not be computed for a cell is listed separately and does not make the cell fail.</li>
<li><b>The viewer.</b> Each group ends with an interactive viewer: pick a scene, scrub or play the frames, choose
image, |error|, signed error (red: too bright, blue: too dark) or FLIP, on each panel's own scale or one shared
scale; the wheel zooms (nearest-neighbour pixels) and dragging pans every panel together; the cursor reads linear
RGB values. Keys: 0-9 show a panel alone (0: ground truth), f or space flips between the last two (A/B),
n / p next / previous, [ ] frames, k play, m display, +/- exposure, s space-time slice of the row under the cursor,
z resets the zoom.</li>
<li><b>Files.</b> Every figure is also an SVG and a PDF (links under it), every table a CSV and a LaTeX file.</li>
</ul>"""
