"""Method ``fxaa``: NVIDIA FXAA 3.11 (Timothy Lottes, 2011), "quality" PC path, on the point-sampled image.

The image of one sample per pixel at the pixel centre (``point``; ``[shaded]`` scenes
shaded there, see :class:`aaeval.renderers.offsets.OffsetSampler`) is encoded to sRGB,
filtered by FXAA 3.11's ``FxaaPixelShader`` (``FXAA_PC``, ``FXAA_PC_CONSOLE 0``) and decoded
back to linear. Luma is computed from the sRGB-encoded colour as the FXAA 3.11 header asks
of its pre-pass ("luma must be stored in the alpha channel ... in a perceptual space":
``dot(rgb, (0.299, 0.587, 0.114))``, ``luma=rgb``) or, with ``luma=green``, is the encoded
green channel (``FXAA_GREEN_AS_LUMA 1``). Texture fetches are bilinear with clamp-to-edge
addressing, on the encoded colour (an RGBA8 texture read without sRGB decoding).

Every pixel runs the shader's steps in lockstep as numpy arrays (no per-pixel loop): the
local contrast test and early exit, the horizontal/vertical edge choice, the sub-pixel
term ``subpix * (smoothstep(|mean3x3 - M| / range))**2`` (the shader's ``subpixC .. subpixH``),
the search along the edge in the steps of the quality preset (``FXAA_QUALITY__P0..P{PS-1}``:
preset 12 and 39 below, from the 3.11 source), and the final bilinear fetch offset
across the edge by ``max(edge offset, subpixel offset)``.

A consequence of the published algorithm: a straight step edge is not left alone. Its
search never ends (the edge runs on), so its edge offset is 0, but the sub-pixel term is
not: next to a vertical 0/1 step, the 3x3 mean differs from M by 1/3 of the range, so both
pixels along the step move ``0.75 * (7/27)**2 = 0.0504`` of the way towards the other side
(``subpix=0`` turns the term off and leaves the step exactly alone).
"""

from __future__ import annotations

import numpy as np

from aaeval.renderers.offsets import OffsetSampler
from aaeval.renderers.registry import Option, register_method
from aaeval.renderers.sampling import warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_fxaa", "fxaa", "PRESETS", "srgb_encode", "srgb_decode"]

#: FXAA 3.11 quality presets: the search steps FXAA_QUALITY__P0 .. P{PS-1}
PRESETS: dict[int, tuple[float, ...]] = {
    12: (1.0, 1.5, 2.0, 4.0, 12.0),
    39: (1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0),
}
LUMA_WEIGHTS = np.array([0.299, 0.587, 0.114])


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1), extended by its formula above 1."""
    x = np.maximum(np.asarray(linear, dtype=np.float64), 0.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    """Inverse of :func:`srgb_encode`."""
    s = np.asarray(encoded, dtype=np.float64)
    return np.where(s <= 0.04045, s / 12.92, np.power((np.maximum(s, 0.04045) + 0.055) / 1.055, 2.4))


def _fetch(tex: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Bilinear fetch with clamp-to-edge at index coordinates (texel (r, c) centred at x=c, y=r)."""
    h, w = tex.shape[:2]
    x0 = np.floor(x)
    y0 = np.floor(y)
    fx = x - x0
    fy = y - y0
    x0 = x0.astype(np.int64)
    y0 = y0.astype(np.int64)
    xa, xb = np.clip(x0, 0, w - 1), np.clip(x0 + 1, 0, w - 1)
    ya, yb = np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1)
    if tex.ndim == 3:
        fx = fx[:, None]
        fy = fy[:, None]
    top = tex[ya, xa] * (1 - fx) + tex[ya, xb] * fx
    bottom = tex[yb, xa] * (1 - fx) + tex[yb, xb] * fx
    return top * (1 - fy) + bottom * fy


def fxaa(encoded: np.ndarray, *, preset: int = 39, subpix: float = 0.75, edge_threshold: float = 0.166,
         edge_threshold_min: float = 0.0833, luma: str = "rgb") -> np.ndarray:
    """FXAA 3.11 quality on an sRGB-encoded (H, W, 3) image; returns the encoded result.

    ``subpix`` is ``fxaaQualitySubpix``, ``edge_threshold`` ``fxaaQualityEdgeThreshold``,
    ``edge_threshold_min`` ``fxaaQualityEdgeThresholdMin`` (the 3.11 defaults).
    """
    steps = PRESETS[preset]
    img = np.asarray(encoded, dtype=np.float64)
    h, w = img.shape[:2]
    L = img[:, :, 1].copy() if luma == "green" else img @ LUMA_WEIGHTS
    pad = np.pad(L, 1, mode="edge")

    def at(dx, dy):
        return pad[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w]

    lumaM = L
    lumaS, lumaE, lumaN, lumaW = at(0, 1), at(1, 0), at(0, -1), at(-1, 0)
    rangeMax = np.maximum(np.maximum(lumaN, lumaW), np.maximum(lumaE, np.maximum(lumaS, lumaM)))
    rangeMin = np.minimum(np.minimum(lumaN, lumaW), np.minimum(lumaE, np.minimum(lumaS, lumaM)))
    rng = rangeMax - rangeMin
    work = ~(rng < np.maximum(edge_threshold_min, rangeMax * edge_threshold))
    out = img.copy()
    if not work.any():
        return out
    r, c = np.nonzero(work)
    m = lumaM[work]
    n, s, e, wv = lumaN[work], lumaS[work], lumaE[work], lumaW[work]
    nw, se, ne, sw = at(-1, -1)[work], at(1, 1)[work], at(1, -1)[work], at(-1, 1)[work]
    rg = rng[work]

    lumaNS = n + s
    lumaWE = wv + e
    subpixNSWE = lumaNS + lumaWE
    edgeHorz1 = -2.0 * m + lumaNS
    edgeVert1 = -2.0 * m + lumaWE
    lumaNESE = ne + se
    lumaNWNE = nw + ne
    edgeHorz2 = -2.0 * e + lumaNESE
    edgeVert2 = -2.0 * n + lumaNWNE
    lumaNWSW = nw + sw
    lumaSWSE = sw + se
    edgeHorz4 = np.abs(edgeHorz1) * 2.0 + np.abs(edgeHorz2)
    edgeVert4 = np.abs(edgeVert1) * 2.0 + np.abs(edgeVert2)
    edgeHorz3 = -2.0 * wv + lumaNWSW
    edgeVert3 = -2.0 * s + lumaSWSE
    edgeHorz = np.abs(edgeHorz3) + edgeHorz4
    edgeVert = np.abs(edgeVert3) + edgeVert4
    subpixNWSWNESE = lumaNWSW + lumaNESE
    horz = edgeHorz >= edgeVert
    subpixA = subpixNSWE * 2.0 + subpixNWSWNESE
    n = np.where(horz, n, wv)
    s = np.where(horz, s, e)
    subpixB = subpixA * (1.0 / 12.0) - m
    gradientN = n - m
    gradientS = s - m
    lumaNN = n + m
    lumaSS = s + m
    pairN = np.abs(gradientN) >= np.abs(gradientS)
    gradient = np.maximum(np.abs(gradientN), np.abs(gradientS))
    lengthSign = np.where(pairN, -1.0, 1.0)
    # (rg is 0 only when both thresholds are 0 on a flat neighbourhood: no sub-pixel term)
    subpixC = np.clip(np.abs(subpixB) / np.where(rg > 0, rg, np.inf), 0.0, 1.0)

    # positions in index coordinates; offNP is (1, 0) along a horizontal edge, else (0, 1)
    mx, my = c.astype(np.float64), r.astype(np.float64)
    offx = np.where(horz, 1.0, 0.0)
    offy = 1.0 - offx
    bx = mx + np.where(horz, 0.0, lengthSign * 0.5)
    by = my + np.where(horz, lengthSign * 0.5, 0.0)
    nx, ny = bx - offx * steps[0], by - offy * steps[0]
    px, py = bx + offx * steps[0], by + offy * steps[0]
    subpixD = -2.0 * subpixC + 3.0
    endN = _fetch(L, nx, ny)
    subpixE = subpixC * subpixC
    endP = _fetch(L, px, py)
    lumaNN = np.where(pairN, lumaNN, lumaSS)
    gradientScaled = gradient * 1.0 / 4.0
    lumaMM = m - lumaNN * 0.5
    subpixF = subpixD * subpixE
    lumaMLTZero = lumaMM < 0.0
    endN = endN - lumaNN * 0.5
    endP = endP - lumaNN * 0.5
    doneN = np.abs(endN) >= gradientScaled
    doneP = np.abs(endP) >= gradientScaled
    for i in range(1, len(steps)):
        if i >= 2:  # the shader reads again (for the sides not done) before every step after P1
            todoN, todoP = ~doneN, ~doneP
            if todoN.any():
                endN[todoN] = _fetch(L, nx[todoN], ny[todoN]) - lumaNN[todoN] * 0.5
            if todoP.any():
                endP[todoP] = _fetch(L, px[todoP], py[todoP]) - lumaNN[todoP] * 0.5
            doneN = np.abs(endN) >= gradientScaled
            doneP = np.abs(endP) >= gradientScaled
        nx = np.where(doneN, nx, nx - offx * steps[i])
        ny = np.where(doneN, ny, ny - offy * steps[i])
        px = np.where(doneP, px, px + offx * steps[i])
        py = np.where(doneP, py, py + offy * steps[i])
        if (doneN & doneP).all():
            break
    dstN = np.where(horz, mx - nx, my - ny)
    dstP = np.where(horz, px - mx, py - my)
    goodSpanN = (endN < 0.0) != lumaMLTZero
    goodSpanP = (endP < 0.0) != lumaMLTZero
    spanLength = dstP + dstN
    directionN = dstN < dstP
    dst = np.minimum(dstN, dstP)
    goodSpan = np.where(directionN, goodSpanN, goodSpanP)
    subpixG = subpixF * subpixF
    pixelOffset = dst * (-1.0 / spanLength) + 0.5
    subpixH = subpixG * subpix
    pixelOffsetGood = np.where(goodSpan, pixelOffset, 0.0)
    pixelOffsetSubpix = np.maximum(pixelOffsetGood, subpixH)
    fx = mx + np.where(horz, 0.0, pixelOffsetSubpix * lengthSign)
    fy = my + np.where(horz, pixelOffsetSubpix * lengthSign, 0.0)
    out[r, c] = _fetch(img, fx, fy)
    return out


@register_method(
    "fxaa",
    summary="FXAA 3.11 (Lottes 2011), quality preset 39 or 12, on the point-sampled image in sRGB",
    options={
        "preset": Option(int, 39, "FXAA 3.11 quality preset (search steps)", choices=tuple(sorted(PRESETS))),
        "subpix": Option(float, 0.75, "fxaaQualitySubpix: amount of sub-pixel aliasing removal", minimum=0.0,
                         maximum=1.0),
        "edge_threshold": Option(float, 0.166, "fxaaQualityEdgeThreshold: local contrast needed, relative to max luma",
                                 minimum=0.0, maximum=1.0),
        "edge_threshold_min": Option(float, 0.0833, "fxaaQualityEdgeThresholdMin: darkest contrast processed",
                                     minimum=0.0, maximum=1.0),
        "luma": Option(str, "rgb", "luma of the sRGB colour: rgb (0.299, 0.587, 0.114) or green (FXAA_GREEN_AS_LUMA)",
                       choices=("rgb", "green")),
    },
    warmup=lambda: render_fxaa(warmup_scene()),
    samples=lambda o: 1,
    memory=lambda scene, o: 40 * 8 * scene.width * scene.height,
)
def render_fxaa(scene: Scene, preset: int = 39, subpix: float = 0.75, edge_threshold: float = 0.166,
                edge_threshold_min: float = 0.0833, luma: str = "rgb") -> np.ndarray:
    point = OffsetSampler(scene).sample(0.0, 0.0)
    encoded = srgb_encode(point)
    filtered = fxaa(encoded, preset=preset, subpix=subpix, edge_threshold=edge_threshold,
                    edge_threshold_min=edge_threshold_min, luma=luma)
    # pixels FXAA left alone keep their linear value (no round trip through sRGB)
    changed = np.any(filtered != encoded, axis=-1, keepdims=True)
    return np.where(changed, srgb_decode(filtered), point)
