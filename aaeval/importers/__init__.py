"""Importers: vector content (SVG, text set in a font) to scene documents.

- :mod:`aaeval.importers.svg` and :mod:`aaeval.importers.text` read the source. SVG's
  document checks are :mod:`~aaeval.importers.svgdocument`, its tree walk
  :mod:`~aaeval.importers.svgwalk`; its cascade, colours and lengths
  :mod:`~aaeval.importers.svgstyle` (cssselect2, tinycss2) made into computed styles by
  :mod:`~aaeval.importers.svgcomputed`; path data, shapes and transforms
  :mod:`~aaeval.importers.svgpath`, :mod:`~aaeval.importers.svgtransform` and
  :mod:`~aaeval.importers.svggeometry`; paints,
  strokes, markers, viewports and clip paths :mod:`~aaeval.importers.svgpaint`,
  :mod:`~aaeval.importers.svgstroke`, :mod:`~aaeval.importers.svgmarkers`,
  :mod:`~aaeval.importers.svgviewport`, :mod:`~aaeval.importers.svgclip`; what is not
  imported is listed by :mod:`~aaeval.importers.svgreport`;
- :mod:`aaeval.importers.shapes`, :mod:`~aaeval.importers.flatten`,
  :mod:`~aaeval.importers.fill` (its steps: :mod:`~aaeval.importers.fillpairs`,
  :mod:`~aaeval.importers.fillcut`, :mod:`~aaeval.importers.fillwinding`,
  :mod:`~aaeval.importers.fillrings`) and :mod:`~aaeval.importers.stroke` turn its paths
  into regions (polygons with holes) under a fill rule or a stroke;
- :mod:`aaeval.importers.scene` lays the regions out as a scene document, one depth
  plane per layer; :func:`aaeval.scenes.write.write_scene_document` writes it;
- :mod:`aaeval.importers.limits` bounds what an import may build.

Nothing is imported here: each importer loads its own dependencies (fontTools, an XML
parser) only when used.
"""
