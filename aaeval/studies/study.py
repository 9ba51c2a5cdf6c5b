"""Studies: one folder per seed paper's claim, its sweep, and a README whose measured part is
generated from the sweep's stored results (``aaeval study experiments/NAME``).

A study folder holds::

    config.toml   an experiment config (``aaeval sweep`` accepts it; scene paths relative to it)
    study.toml    the paper, its seed file, and the summaries that bear on the claim
    README.md     the claim, by hand, and between the two markers below the generated part
    results/      the sweep folder (not kept in git; ``aaeval study`` runs or resumes it)

``study.toml``::

    [study]
    paper = "E. Catmull, A Hidden-Surface Algorithm with Anti-Aliasing, SIGGRAPH 1978"
    seed = "000_160fc636db56a9a8.txt"           # the paper's file in the seeds folder

    [[summaries]]
    kind = "sums"                               # see aaeval.studies.summaries.SUMMARIES
    group = "picket-fence"
    title = "Intensity sum per frame"
    steady = ["catmull"]                        # expectations: the claim, stated before the run
    unsteady = ["point"]

Expectations (``steady``/``unsteady``, ``agree``/``disagree``, ``within_noise``, ``below``,
``ratio_above``/``ratio_below``: each summary's ``expects``) are the study's prediction,
written by hand; whether each holds, and the number it turns on, is read from the results.

Every number written between the markers is read from the results folder (``results.parquet``,
``temporal.parquet``, the stored images) or, for ``hidden_lines`` and ``figure``, from the
drawings and figures the summary makes into ``hidden-lines/`` and ``figures/`` of the study
folder (:mod:`aaeval.studies.figures`); none is typed into the study. The hand-written text
around the markers is kept byte for byte; names and text from the files are escaped.

Against a noise-free truth (``catmull``, ``catmull:shading=exact``) nothing is divided by the
truth's error bound, and "within" it means within the bound plus float rounding
(:func:`aaeval.metrics.agreement.truth_of`, the rule the report follows too).

It computes none of a cell's results: the sweep's code version leaves ``aaeval/studies`` out
(as it does the report), so editing a summary never reruns a cell.

This module reads and checks a study folder (:func:`load_study`); running it is
:mod:`aaeval.studies.run`, the generated section :mod:`aaeval.studies.section`, and the summary
kinds with their checks and writers :mod:`aaeval.studies.summaries`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Mapping

from aaeval._toml import read_toml, refuse_unknown_keys
from aaeval.studies.folder import MAX_TEXT, MAX_ITEMS, OUTPUT_FOLDERS, Study, StudyError, brief, refuse_link
from aaeval.studies.readme import read_readme, split_readme
from aaeval.studies.summaries import check_summary


_STUDY_KEYS = {"paper", "seed", "config", "results"}


def load_study(folder: str | Path, results: str | Path | None = None) -> Study:
    """Read ``folder/study.toml`` and check the folder before any work.

    Parameters
    ----------
    folder : str or Path
        The study folder (``experiments/NAME``).
    results : str or Path, optional
        The sweep folder; default ``[study].results`` of ``study.toml``, else ``folder/results``.

    Returns
    -------
    Study

    Raises
    ------
    StudyError
        A file is missing or is a link, the README is too large or lacks the markers (each
        once, BEGIN before END), the config does not load, or a field of ``study.toml`` breaks
        its rule: every field is checked here, against the config's groups, methods, metrics,
        frames and image sizes, so that nothing is refused after the sweep has run.
    """
    from aaeval.sweeps import ConfigError, load_experiment

    folder = Path(folder)
    if folder.is_symlink() or not folder.is_dir():
        raise StudyError(f"{folder}: not a study folder (expected a folder, not a link, with study.toml, "
                         "config.toml, README.md)")
    path = folder / "study.toml"
    if not path.is_file():
        raise StudyError(f"{path}: missing; a study folder names its paper and summaries there")
    refuse_link(path)
    document, _ = read_toml(path, StudyError, "study file")
    refuse_unknown_keys(document, {"study", "summaries"}, str(path), StudyError)
    head = document.get("study")
    if not isinstance(head, Mapping):
        raise StudyError(f"{path}: missing table [study]")
    refuse_unknown_keys(head, _STUDY_KEYS, f"{path}: [study]", StudyError)
    for key in ("paper", "seed"):
        if not isinstance(head.get(key), str) or not head[key].strip() or len(head[key]) > MAX_TEXT:
            raise StudyError(f"{path}: [study].{key} must be a non-empty string of at most {MAX_TEXT} characters")
    for key in ("config", "results"):
        if key in head and (not isinstance(head[key], str) or not head[key].strip()):
            raise StudyError(f"{path}: [study].{key} must be a path (a non-empty string), got {brief(head[key])}")
    config = folder / head.get("config", "config.toml")
    if not config.is_file():
        raise StudyError(f"{config}: the study's experiment config is missing")
    readme = folder / "README.md"
    if not readme.is_file():
        raise StudyError(f"{readme}: missing; the study's claim is written there")
    refuse_link(readme)
    split_readme(read_readme(readme), readme)  # markers checked before the sweep runs
    for name in OUTPUT_FOLDERS:
        refuse_link(folder / name)
        if (folder / name).exists() and not (folder / name).is_dir():
            raise StudyError(f"{folder / name}: not a folder; the study writes its drawings there")
    try:
        experiment = load_experiment(config)
    except ConfigError as exc:
        raise StudyError(str(exc)) from None
    summaries = document.get("summaries", [])
    if not isinstance(summaries, list) or not summaries:
        raise StudyError(f"{path}: needs at least one [[summaries]] table")
    if len(summaries) > MAX_ITEMS:
        raise StudyError(f"{path}: {len(summaries)} [[summaries]] tables, over the limit of {MAX_ITEMS}")
    groups = {g.name: g for g in experiment.groups}
    for i, item in enumerate(summaries):
        check_summary(item, f"{path}: summaries[{i}]", groups, folder)
    if results is None:  # the file's own choice stays inside the study folder; --results is the user's
        inside = Path(head.get("results", "results"))
        if inside.is_absolute() or ".." in inside.parts:
            raise StudyError(f"{path}: [study].results must be a folder inside the study folder, got {brief(str(inside))}")
        refuse_link(folder / inside)
    out = Path(results) if results is not None else folder / head.get("results", "results")
    return Study(folder, head["paper"].strip(), head["seed"].strip(), config, readme, out, tuple(summaries),
                 experiment)
