# ddes-digest: c96a2ec050531fe53e1467e06c1036b7529ef4df6387c74e179421738a842a67
# %% [markdown]
# # For instructors: grading with ddes
#
# `ddes grade` runs a student's rospy nodes in a confined child process, in lockstep with a
# trusted simulated world, and scores them from what happened in that world (its trace and the
# messages in it), never from anything the student's code says about itself. A grade is
# deterministic: each scenario has a trace digest, and any failing scenario can be replayed
# exactly, with a picture. To trust a grader, feed it **mutants** (the reference solution with
# one typical bug each): every bug must lose the criteria it should, and correct variants must
# lose nothing (the **kill matrix**). To trust a reference, grade it over many seeds (a **seed
# sweep**): it must never lose a point.
#
# This notebook grades public scenarios only (`public=True`) to stay fast; `ddes grade` without
# `--public` adds the hidden ones.

# %%
import hashlib
import json
import os
import shutil
import tempfile
from pathlib import Path

import yaml
from IPython.display import Image
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

import ddes
from ddes.display.figure import new_figure
from ddes.grading import grade
from ddes.grading.exercise import REGISTRY
from ddes.grading.mutants import apply_diff, load_mutants, sensitivity
from ddes.grading.replay import replay
from ddes.grading.sweep import sweep


def course_root():
    """The course's checkout (the folder holding solutions/), wherever the notebook runs:
    next to the ddes package (a source checkout, an editable install), else above the
    notebook Jupyter says it runs, else the working folder or one above it (Jupyter starts the
    kernel in the notebook's folder)."""
    here = Path.cwd().resolve()
    notebook = Path(os.environ.get("JPY_SESSION_NAME", here / "notebook")).resolve().parent
    for root in [Path(ddes.__file__).resolve().parent.parent, notebook.parent, here,
                 *here.parents]:
        if (root / "solutions" / "ex3_pillar").is_dir():
            return root
    raise FileNotFoundError("solutions/ex3_pillar not found: open this notebook from the "
                            "course's checkout (course_notebooks/ next to solutions/)")


ROOT = course_root()
work = Path(tempfile.mkdtemp())
ex3 = REGISTRY.get("ex3_pillar")
reference = ROOT / "solutions" / "ex3_pillar"
digests = []


def shown(text, *folders):
    """The text with the temporary and checkout folders shortened, as a student would see."""
    for folder, name in folders:
        text = text.replace(str(folder), name)
    return text

# %% [markdown]
# ## The reference and one mutant
#
# Exercise 3's reference solution, then the mutant `gain_sign` (the P law with the wrong sign:
# `-gain * angle`), applied to a copy with ddes's strict diff applier.

# %%
report = grade(ex3, reference, public=True)
print(shown(report.to_text(), (reference, "solutions/ex3_pillar")))
digests += report.digests.values()

mutant = {m.name: m for m in load_mutants(reference, ex3)}["gain_sign"]
print(f"mutant {mutant.name} ({mutant.kind}): {mutant.description.split(':')[0]}")
copy = work / "gain_sign"
shutil.copytree(reference, copy, ignore=shutil.ignore_patterns("mutants", "__pycache__"))
print("patched:", apply_diff(copy, mutant.diff.read_text(encoding="utf-8"), mutant.name))

# %%
bad = grade(ex3, copy, public=True)
print(shown(bad.to_text(), (copy, "gain_sign")))
digests += bad.digests.values()

# %% [markdown]
# The same grade as Gradescope's `results.json`:

# %%
bad.write_results(work / "results.json")
results = json.loads((work / "results.json").read_text())
results["execution_time"] = "(varies)"
print(shown(json.dumps(results, indent=1), (copy, "gain_sign")))

# %% [markdown]
# ## Replay the failure
#
# Each lost criterion names a replay command. Running that scenario again gives the digest the
# grade recorded, and a top view of the run: steering away from the pillar.

# %% tags=["plot"]
again = replay(ex3, copy, "public", seed=0, picture=work / "gain_sign.png")
print(shown(again.to_text(), (copy, "gain_sign"), (work, "tmp")))
print("same digest as the grade:", again.digest == bad.digests["public"])
digests.append(again.digest)
Image(filename=str(work / "gain_sign.png"))

# %% [markdown]
# ## A kill matrix
#
# `ddes grade sensitivity ex2_package` grades the reference and all 19 mutants of exercise 2
# (about 30 s; exercise 3's 21 take about 60 s, see docs/grading.md). Here a copy of the
# solution keeps three of them: two bugs and one correct variant. Cells are points lost; `*`
# marks the criteria a bug must lose.

# %%
ex2 = REGISTRY.get("ex2_package")
solutions = work / "solutions"
subset = solutions / "ex2_package"
shutil.copytree(ROOT / "solutions" / "ex2_package", subset,
                ignore=shutil.ignore_patterns("__pycache__"))
keep = ["f_string", "hard_coded_topic", "max_range"]
meta = yaml.safe_load((subset / "mutants" / "mutants.yaml").read_text(encoding="utf-8"))
for diff in (subset / "mutants").glob("*.diff"):
    if diff.stem not in keep:
        diff.unlink()
(subset / "mutants" / "mutants.yaml").write_text(yaml.safe_dump({k: meta[k] for k in keep}))
matrix = sensitivity(ex2, solutions)
print(matrix.to_text())
for row in matrix.rows:
    digests += row.report.digests.values()

# %% tags=["plot"]
fig = new_figure(figsize=(7.5, 2.9))
ax = fig.add_subplot(1, 1, 1)
top = {c.id: c.max_points for c in ex2.criteria}
cells = [[row.lost.get(c, 0.0) / top[c] for c in matrix.criteria] for row in matrix.rows]
ax.imshow(cells, cmap="Reds", vmin=0, vmax=1, aspect="auto")
for i, row in enumerate(matrix.rows):
    for j, c in enumerate(matrix.criteria):
        lost = row.lost.get(c, 0.0)
        ax.text(j, i, (f"{lost:.3g}" if lost else ".") + ("*" if c in row.expected else ""),
                ha="center", va="center", fontsize=8)
ax.set_xticks(range(len(matrix.criteria)), matrix.criteria)
names = [r.name if r.kind == "reference" else f"{r.name} ({r.kind})" for r in matrix.rows]
ax.set_yticks(range(len(matrix.rows)), names)  # one label per row
ax.set_xlabel("criterion")
ax.set_ylabel("submission (kind)")
ax.legend(handles=[
    Patch(color="tab:red", label="shade: share of the criterion lost (0-100 %)"),
    Line2D([], [], marker="$2.5$", markersize=12, color="black", linestyle="none",
           label="number: points lost"),
    Line2D([], [], marker=".", markersize=4, color="black", linestyle="none",
           label="nothing lost"),
    Line2D([], [], marker="$*$", markersize=8, color="black", linestyle="none",
           label="a criterion the bug must lose")],
    loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False)
ax.set_title("ex2_package kill matrix: share of each criterion lost")
fig.tight_layout()
fig

# %% [markdown]
# ## A seed sweep
#
# Each seed changes the worlds of the scenarios (start pose, noise). Exercise 3's reference
# over four seeds; a CI job sweeps 20 (`ddes grade sweep ex3_pillar solutions/ex3_pillar
# --seeds 0:20 --fail-under 100`), a release 200.

# %% tags=["plot"]
swept = sweep(ex3, reference, range(4), public=True)
print(shown(swept.to_text(), (reference, "solutions/ex3_pillar")))
for _, r in swept.grades:
    digests += r.digests.values()
swept.figure()

# %% [markdown]
# One digest over every graded scenario above: a change in the simulator, the grader or the
# lockstep shows here.

# %% tags=["digest"]
print(hashlib.sha256(" ".join(digests).encode()).hexdigest())

# %% [markdown]
# ## Try this
#
# Grade another mutant of `solutions/ex3_pillar/mutants/` (`stops_short`, `marker_at_robot`),
# or grade without `public=True` and compare the scores: `hard_coded_gain` loses only in the
# hidden scenarios. The command line does the same: `ddes grade ex3_pillar SUBMISSION --out
# DIR`, `ddes grade replay …`, `ddes grade sensitivity ex3_pillar`, `ddes grade sweep …`.
