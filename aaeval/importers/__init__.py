"""Importers: vector content (SVG, text set in a font) to scene documents.

- :mod:`aaeval.importers.svg` and :mod:`aaeval.importers.text` read the source; SVG's
  cascade, colours and lengths are :mod:`~aaeval.importers.svgstyle` (cssselect2,
  tinycss2), its path data, shapes and transforms :mod:`~aaeval.importers.svgpath`;
- :mod:`aaeval.importers.shapes`, :mod:`~aaeval.importers.flatten`,
  :mod:`~aaeval.importers.fill` and :mod:`~aaeval.importers.stroke` turn its paths into
  regions (polygons with holes) under a fill rule or a stroke;
- :mod:`aaeval.importers.scene` lays the regions out as a scene document, one depth
  plane per layer; :func:`aaeval.scenes.write.write_scene_document` writes it;
- :mod:`aaeval.importers.limits` bounds what an import may build.

Nothing is imported here: each importer loads its own dependencies (fontTools, an XML
parser) only when used.
"""
