# %% [markdown]
# # Four anti-aliasing methods on one scene
#
# A notebook in percent cells (Jupyter, VS Code and jupytext open it as a notebook; `python
# examples/notebook.py` runs it as a script). It loads a scene, renders it with four
# methods, compares them against the exact `catmull` box filter, plots error against
# render time and shows the images. The test suite runs it (tests/cli/test_notebook.py) with
# `AAEVAL_NOTEBOOK_OUT` naming where its figures go (default: the current folder).

# %%
import os
from pathlib import Path

import matplotlib

if "ipykernel" not in __import__("sys").modules:
    matplotlib.use("Agg")  # a script or CI: figures go to files, no window
import matplotlib.pyplot as plt

import aaeval
from aaeval.imageio import linear_to_srgb8

OUT = Path(os.environ.get("AAEVAL_NOTEBOOK_OUT", "."))
SCENE = Path(__file__).resolve().parents[1] / "configs" / "scenes" / "fan.toml" if "__file__" in globals() \
    else Path("../configs/scenes/fan.toml")
METHODS = ["point", "supersample:k=4", "msaa", "fxaa"]

# %% [markdown]
# ## The scene
# 24 wedges meeting in one pixel: a few samples per pixel cannot see 24 colours.

# %%
scene = aaeval.load_scene(SCENE)
scene  # in Jupyter: the picture (rendered with catmull); here: one line

# %% [markdown]
# ## Four methods, and the exact reference

# %%
images = {spec: aaeval.render(scene, spec) for spec in ["catmull", *METHODS]}
{spec: image.shape for spec, image in images.items()}

# %% [markdown]
# ## Compared against catmull
# One row per method: RMSE over the image and over the pixels an edge crosses, render time.

# %%
table = aaeval.compare(scene, METHODS, reference="catmull", metrics=["rmse", "edge_rmse"], repeats=3)
assert table["error"].isna().all()
table[["method", "rmse", "edge_rmse", "render_s"]]

# %% [markdown]
# ## Error against time

# %%
fig, ax = plt.subplots(figsize=(6, 4))
ax.loglog(table["render_s"] * 1e3, table["rmse"], "o")
for row in table.itertuples():
    ax.annotate(row.method, (row.render_s * 1e3, row.rmse), textcoords="offset points", xytext=(4, 4))
ax.set_xlabel("render time (ms, median of 3)")
ax.set_ylabel("RMSE against catmull")
fig.tight_layout()
fig.savefig(OUT / "error-vs-time.png", dpi=150)

# %% [markdown]
# ## The images (sRGB), the exact one first

# %%
fig, axes = plt.subplots(1, len(images), figsize=(3 * len(images), 3))
for ax, (spec, image) in zip(axes, images.items()):
    ax.imshow(linear_to_srgb8(image), interpolation="nearest")
    ax.set_title(spec)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "images.png", dpi=150)
