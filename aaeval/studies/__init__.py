"""Studies: a folder under ``experiments/`` that reproduces one seed paper's claim.

:mod:`aaeval.studies.study` reads and checks a study folder, :mod:`aaeval.studies.run` runs (or
resumes) its sweep and :mod:`aaeval.studies.section` writes the generated part of its README from
the stored results, one summary kind at a time (:data:`aaeval.studies.summaries.SUMMARIES`).
The package lives outside :mod:`aaeval.report` because it runs sweeps and draws hidden lines,
and the report package renders and measures nothing; like the report it cannot change a cell's
result, so its source is not part of the code version a cell's key holds
(:data:`aaeval.sweeps.cache_keys._PRESENTATION`).
"""
