"""Rendering methods, one module per method, all in one registry.

Importing this package registers every built-in method. Use :func:`render` with a spec
(a :class:`MethodSpec`, or a string: ``"catmull"``, ``"supersample:k=4"``) or look methods up in
:data:`METHODS`.
"""

from aaeval.renderers.registry import (
    METHODS,
    Method,
    MethodError,
    MethodSpec,
    Option,
    format_spec,
    parse_spec,
    register_method,
    render,
    render_timed,
    resolve,
)

# one import per method module; each registers its methods
from aaeval.renderers import catmull  # noqa: E402,F401
from aaeval.renderers import point  # noqa: E402,F401
from aaeval.renderers import supersample  # noqa: E402,F401
from aaeval.renderers import jitter  # noqa: E402,F401
from aaeval.renderers import abuffer  # noqa: E402,F401
from aaeval.renderers import skia_painter  # noqa: E402,F401
from aaeval.renderers import blend2d_painter  # noqa: E402,F401
from aaeval.renderers import mitsuba  # noqa: E402,F401
from aaeval.renderers import weiler_atherton  # noqa: E402,F401
from aaeval.renderers import freetype  # noqa: E402,F401
from aaeval.renderers import resvg  # noqa: E402,F401
from aaeval.renderers import msaa  # noqa: E402,F401
from aaeval.renderers import fxaa  # noqa: E402,F401
from aaeval.renderers import taa  # noqa: E402,F401

__all__ = [
    "METHODS",
    "Method",
    "MethodError",
    "MethodSpec",
    "Option",
    "format_spec",
    "parse_spec",
    "register_method",
    "render",
    "render_timed",
    "resolve",
]

# methods from other packages (entry points "aaeval.methods"), after the built-ins; metric
# plugins too, so that every process that renders (sweep workers included) knows them
from aaeval.plugins import load_plugins  # noqa: E402

load_plugins("aaeval.methods")
load_plugins("aaeval.metrics")
