"""The default scene: a quick verification of the reduced beam against the 3D solid.

What ``bash scripts/main.sh`` runs on a fresh machine, in a few minutes:

1. Natural frequencies at the Table 1 speed (``modal_rpm``, 8500 r/min) from
   each model of ``modal_models`` (reduced Timoshenko beam, 5N DOF, and the
   solid FE on the scene's mesh), paired by mode label (flap1, chord1, ...:
   the beam restrains torsion, the solid does not), beside the paper's
   Table 1 (beam N = 6 and its ANSYS reference); the shell (docs/shell.md)
   beside them, the second FE formulation.
2. The Fig. 8 transient (the scene's speed, 10000 r/min, N0 = 0, alpha =
   15 deg) from each model of ``transient_models``: the fig8 study
   (comparisons.fig8) run on this scene's parameters into ``fig8/``, with
   the most detailed model run as its reference: contact forces, loops,
   states, tip displacements, agreement (NRMSE over ``window_periods``)
   and the cost of each beside the paper's Table 3.

Everything comes from ``shroud.analysis.api`` and the fig8 study; this module only
arranges and reports. :func:`conclusions` turns the returned numbers into what
the report concludes. The study is compute (:func:`compute` -> :class:`DefaultResult`,
the fig8 study's compute inside) -> plot -> report.
"""

from __future__ import annotations

import csv
import dataclasses
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from comparisons import convergence, paper
from comparisons._study import study
from shroud.analysis import api
from shroud.core import registry
from shroud.base.errors import InputError
from shroud.core.plotting import MODEL_COLOURS, figure, save
from shroud.core.verdict import NOT_DECIDED, BandVerdict
from shroud.base.markdown import demote, markdown_table, relink, seconds
from shroud.base.outputs import open_replacing, write_text

if TYPE_CHECKING:
    from comparisons import fig8


def _fig8():
    """The fig8 study, imported only where a scene has transient models: it brings the contact law and the
    integrator, which a modal-only scene does not build (tests/test_lean_build.py)."""
    from comparisons import fig8
    return fig8

OPTIONS = {
    "modal_rpm": 8500.0,                      # r/min, the speed of the paper's Table 1
    "n_modes": 5,                               # the solid has torsion1 among its first four
    "modal_models": ["reduced", "extended", "shell", "fe"],
    "transient_models": ["reduced", "full", "extended", "shell-reduced", "fe-reduced"],
    "window_periods": 10,                      # excitation periods compared and plotted
}

# Paper Table 1 (8500 r/min): the beam model at N = 6 and its ANSYS Beam188 reference, Hz.
PAPER_TABLE1 = {"paper beam N=6": paper.TABLE1_REDUCED[6], "paper ANSYS": paper.TABLE1_FE}
PAPER_TABLE1_LABELS = paper.TABLE1_LABELS
# The most detailed model present is the reference of the transient comparison.
FIDELITY = ("fe", "fe-reduced", "shell", "shell-reduced", "full", "extended", "reduced")


def check(scene) -> None:
    """Options that name models or counts are checked before anything runs."""
    o = scene.options
    for key, allowed in (("modal_models", registry.names("modal")), ("transient_models", registry.names("transient"))):
        bad = [m for m in o[key] if m not in allowed]
        if bad or len(set(o[key])) != len(o[key]):
            raise InputError(f"options.{key}", f"{o[key]!r}; allowed: distinct names from {', '.join(allowed)}")
    if o["n_modes"] < 1:
        raise InputError("options.n_modes", f"{o['n_modes']} is out of range; allowed: an integer >= 1")
    if o["modal_rpm"] < 0:
        raise InputError("options.modal_rpm", f"{o['modal_rpm']} is out of range; allowed: a speed >= 0 r/min")
    if o["transient_models"]:
        scene.params.time_step       # refuses a speed of 0 (shroud.params)
        _fig8().check(_fig8_scene(scene))


@dataclass(frozen=True)
class DefaultResult:
    """The frequencies of every modal model paired by label, and the fig8 study on this scene."""

    modal: dict | None             # frequencies by label, differences to the solid, costs (frequencies())
    transient: fig8.Fig8Result | None   # the fig8 study's result on this scene's transient models

    def to_json(self) -> dict:
        results: dict = {}
        if self.modal is not None:
            results["modal"] = self.modal
        if self.transient is not None:
            results["fig8"] = self.transient.to_json()
        results["conclusions"] = conclusions(results)
        return results


def compute(scene, out: Path) -> DefaultResult:
    """The modal models at ``modal_rpm``; the fig8 study's computation (time series into ``out``/fig8)."""
    check(scene)
    o = scene.options
    modal = None
    if o["modal_models"]:
        modal = frequencies({m: api.modal(scene.params, m, rpm=o["modal_rpm"], n_modes=o["n_modes"])
                             for m in o["modal_models"]}, o["modal_rpm"])
    transient = _fig8().compute(_fig8_scene(scene), _fig8_folder(out)) if o["transient_models"] else None
    return DefaultResult(modal=modal, transient=transient)


def plot(result: DefaultResult, scene, out: Path) -> list[str]:
    """The frequencies (CSV and figure); the fig8 study's figures, tables and report into ``out``/fig8."""
    files = []
    if result.modal is not None:
        files.append(_write_frequencies(result.modal, out).name)
    if result.transient is not None:
        fig8_scene, folder = _fig8_scene(scene), _fig8_folder(out)
        shown = _fig8().plot(result.transient, fig8_scene, folder)
        write_text(folder / "report.md", _fig8().report(result.transient, fig8_scene, shown))
        files += [f"fig8/{f}" for f in shown]
    return files


def report(result: DefaultResult, scene, files: list[str]) -> str:
    sections = [f"# {scene.title}\n\n"]
    if result.modal is not None:
        sections.append(_frequency_report(result.modal))
        sections.append(_frequency_verdicts(result.to_json()["conclusions"]["frequency_vs_solid"]))
    if result.transient is not None:
        sections.append(_fig8_report(result.transient, scene))
    return "".join(sections)


run = study(compute, plot, report, writes=True)


def conclusions(results: dict) -> dict:
    """What the report concludes, as data, from the numbers ``run`` returns (a results.json gives them):
    per mode and model, its frequency "higher", "lower" or "the same" as the solid FE's (a BandVerdict: the
    band is the solid mesh's own tolerance, comparisons.convergence.OPTIONS["tolerance_pct"], since a smaller
    difference is not resolved by the solid; no margin beyond it is measured here); the fig8 study's
    conclusions on the transient."""
    tol = convergence.OPTIONS["tolerance_pct"]
    found: dict = {}
    if "modal" in results:
        found["frequency_vs_solid"] = {
            row["label"]: {key[:-len("_vs_fe_percent")]: BandVerdict(
                v if v is not None else math.nan, tol, 0.0, above="higher", below="lower", between="the same",
                reason="the band is the solid mesh's tolerance (scenes/convergence.toml); a difference inside it "
                       "is not resolved by the solid", unit="%")
                for key, v in row.items() if key.endswith("_vs_fe_percent")}
            for row in results["modal"]["rows"]}
    if "fig8" in results:
        found["fig8"] = results["fig8"]["conclusions"]
    return found


def _frequency_verdicts(verdicts: dict) -> str:
    """One line per model: the modes where it is higher, lower and the same as the solid (with the numbers)."""
    models = sorted({m for v in verdicts.values() for m in v})
    if not models:
        return ""
    tol = convergence.OPTIONS["tolerance_pct"]
    lines = [f"Against the solid (each verdict a difference in % against a band of +-{tol:g} %, the solid mesh's "
             "own tolerance (scenes/convergence.toml), inside which it counts as the same; no margin beyond the "
             "band is measured here):\n"]
    for m in models:
        found = {lab: v[m] for lab, v in verdicts.items() if m in v}
        by = {word: [f"{lab} ({found[lab].value:+.2f} %)" for lab in found if found[lab].answer == word]
              for word in ("higher", "lower", "the same", NOT_DECIDED)}
        lines.append(f"- {m}: " + "; ".join(f"{word} in {', '.join(labs)}" for word, labs in by.items() if labs) + ".")
    return "\n".join(lines) + "\n\n"


# --- 1. frequencies -----------------------------------------------------------

def frequencies(modal: dict, rpm: float) -> dict:
    """Frequencies by label for each model; relative difference to the solid FE."""
    by_label = {m: r.by_label() for m, r in modal.items()}
    # a mode is listed when two models or more have it (the extended beam and the solid: torsion1),
    # every mode of a model compared with none
    shared = min(2, len(by_label))
    labels = [lab for lab in _ordered_labels(modal) if sum(lab in f for f in by_label.values()) >= shared]
    reference = "fe" if "fe" in by_label else None
    rows = []
    for lab in labels:
        row = {"label": lab, **{m: by_label[m].get(lab) for m in by_label}}
        if reference and lab in by_label[reference]:
            for m in by_label:
                if m != reference and lab in by_label[m]:
                    row[f"{m}_vs_fe_percent"] = 100 * (by_label[m][lab] / by_label[reference][lab] - 1)
        if rpm == 8500.0 and lab in PAPER_TABLE1_LABELS:
            i = PAPER_TABLE1_LABELS.index(lab)
            row.update({k: v[i] for k, v in PAPER_TABLE1.items()})
        rows.append(row)
    return {"rpm": rpm, "rows": rows, "unpaired": {m: sorted(set(f) - set(labels)) for m, f in by_label.items()},
            "cost": {m: {"dofs": r.dofs, "elapsed_s": r.elapsed_s} for m, r in modal.items()},
            "figure": "frequencies.png", "csv": "frequencies.csv"}


def _write_frequencies(modal: dict, out: Path) -> Path:
    """The frequencies' CSV and figure (names in ``modal``)."""
    rows = modal["rows"]
    with open_replacing(out / modal["csv"]) as fh:
        writer = csv.DictWriter(fh, fieldnames=sorted({k for r in rows for k in r}, key=_column_order))
        writer.writeheader()
        writer.writerows(rows)
    models = list(modal["cost"])
    return _plot_frequencies(rows, models, "fe" if "fe" in models else None, modal["rpm"], out / modal["figure"])


def _ordered_labels(modal: dict) -> list[str]:
    """Every model's labels, in the frequency order of the solid (or of the first model)."""
    first = modal.get("fe", next(iter(modal.values())))
    ordered = [m.label for m in first.modes]
    return ordered + [m.label for r in modal.values() for m in r.modes if m.label not in ordered]


def _column_order(key: str):
    return (key != "label", key.startswith("paper"), "vs" in key, key)


def _plot_frequencies(rows, models, reference, rpm, path: Path) -> Path:
    fig, axes = figure(1, 2, width=7.2, height=2.8)
    x = np.arange(len(rows))
    labels = [r["label"] for r in rows]
    for m in models:
        axes[0, 0].plot(x, [_nan(r[m]) for r in rows], "o-", color=MODEL_COLOURS[m], label=m)
    for k in PAPER_TABLE1:
        if all(k in r for r in rows):
            axes[0, 0].plot(x, [r[k] for r in rows], "x", color=MODEL_COLOURS["paper"], label=k)
    axes[0, 0].set(xticks=x, xticklabels=labels, ylabel="natural frequency (Hz)",
                   title=f"natural frequencies at {rpm:g} r/min")
    axes[0, 0].legend()
    if reference:
        for m in models:
            if m != reference:
                axes[0, 1].plot(x, [_nan(r.get(f"{m}_vs_fe_percent")) for r in rows], "o-", color=MODEL_COLOURS[m],
                                label=m)
        axes[0, 1].axhline(0, color="k", lw=0.6)
        axes[0, 1].set(xticks=x, xticklabels=labels, ylabel="difference to the solid FE (%)",
                       title="models against the 3D solid")
        axes[0, 1].legend()
    else:
        axes[0, 1].set_visible(False)
    return save(fig, path)


def _nan(v):
    return np.nan if v is None else v


def _frequency_report(modal: dict) -> str:
    rows = modal["rows"]
    models = list(modal["cost"])
    header = ["mode"] + [f"{m} (Hz)" for m in models] + \
        [f"{m} vs fe (%)" for m in models if m != "fe" and "fe" in models] + \
        [f"{k} (Hz)" for k in PAPER_TABLE1 if any(k in r for r in rows)]
    table = [[r["label"]] + [r[m] for m in models] +
             [r.get(f"{m}_vs_fe_percent") for m in models if m != "fe" and "fe" in models] +
             [r.get(k) for k in PAPER_TABLE1 if any(k in r for r in rows)] for r in rows]
    cost = markdown_table(["model", "DOF", "wall time"],
                          [[m, c["dofs"], seconds(c["elapsed_s"])] for m, c in modal["cost"].items()])
    unpaired = "; ".join(f"{m}: {', '.join(v)}" for m, v in modal["unpaired"].items() if v)
    return (f"## Natural frequencies at {modal['rpm']:g} r/min\n\n"
            "Modes are paired by their tip-motion label, not by index. The paper's Table 1 "
            "values (beam N = 6, ANSYS beam) are shown where the speed is theirs.\n\n"
            + markdown_table(header, table) + "\n" + cost
            + (f"\nModes found by one model only: {unpaired}.\n" if unpaired else "")
            + f"\n![frequencies]({modal['figure']})\n\n")


# --- 2. the Fig. 8 transient: the fig8 study on this scene's parameters ---------

def _fig8_scene(scene):
    """This scene as a fig8 scene: its models, the most detailed of them as reference."""
    models = scene.options["transient_models"]
    options = {**_fig8().OPTIONS, "models": models, "reference": next(m for m in FIDELITY if m in models),
               "window_periods": scene.options["window_periods"]}
    return dataclasses.replace(scene, study="fig8", options=options)


def _fig8_folder(out: Path) -> Path:
    """Where the fig8 study's files go: ``out``/fig8."""
    folder = out / "fig8"
    folder.mkdir(exist_ok=True)
    return folder


def _fig8_report(transient: fig8.Fig8Result, scene) -> str:
    body = re.sub(r"\A# [^\n]*\n", "", _fig8().report(transient, _fig8_scene(scene), []))
    return "## The Fig. 8 transient and the paper's Table 3\n\n" + relink(demote(body), "fig8") + "\n"
