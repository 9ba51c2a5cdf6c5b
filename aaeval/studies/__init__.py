"""Studies: a folder under ``experiments/`` that reproduces one seed paper's claim.

:mod:`aaeval.studies.study` runs (or resumes) a study's sweep and rewrites the generated part
of its README from the stored results. It lives outside :mod:`aaeval.report` because it
runs sweeps and draws hidden lines, and the report package renders and measures nothing;
like the report it cannot change a cell's result, so its source is not part of the code
version a cell's key holds (:data:`aaeval.sweeps.store._PRESENTATION`).
"""
