"""Specular clamp ``halve`` (``catmull:specular=halve``): half the Phong exponent everywhere.

Import only :mod:`aaeval.specular.methods` here: this group loads while that module is
being imported by the renderers.
"""

from aaeval.specular.methods import register_specular


def halve(corners, n, **options):
    return n / 2


register_specular("halve", summary="example plugin: half the Phong exponent everywhere", clamp=halve)
