"""Campaigns: one TOML file that lists scenes, runs them all, and writes one report.

Layout of a campaign file::

    title = "The paper's studies"
    campaign = ["table1", "fig3", "fig8.toml"]   # scene names (scenes/<name>.toml) or paths
    quick = false                               # true = every scene's coarse version
    [overrides]                                 # per-scene --set lists
    fig8 = ["time.periods=50"]
    [gates.fig8]                                # per-scene gates, over the scene's own [gates]
    "results.versus_reference.reduced.nrmse.v_L" = { max = 0.08 }

``shroud run CAMPAIGN.toml --out DIR`` checks every listed scene (with its
overrides and the command line's ``--set``) before it runs any, then runs
them over local processes, or over MPI ranks under ``mpirun`` (one scene per
rank at a time, each on its own communicator), into ``DIR/<scene>/``, and
stitches ``DIR/report.md`` from their reports. A scene that fails does not
stop the others; its status says why. Each scene's gates (its own ``[gates]``,
the campaign's ``[gates.<scene>]`` and the command line's ``--gate``, which
reaches every scene) are held in its run; the campaign report opens with a
gate summary and ``DIR/junit.xml`` holds every scene's gates.
"""

from __future__ import annotations

import json
import time
import traceback
from dataclasses import dataclass, replace
from pathlib import Path

from shroud.base.errors import InputError
from shroud.base.log import info, warn
from shroud.params import unknown_key
from shroud.base.parallel import map_parallel, mpi_rank, mpi_size, workers
from shroud.base.markdown import seconds
from shroud.base.outputs import write_text
from workbench import junit
from workbench.gates import Gate, from_table, hold, merged
from workbench.report import SceneOutcome, campaign_gate_summary, stitch
from workbench.runner import holding, jsonable, output_folder, run_scene, shielded_from_interrupts, versions
from workbench.scene import load_scene, read_toml

_TOP_KEYS = ("campaign", "title", "description", "quick", "overrides", "gates")


@dataclass(frozen=True)
class Entry:
    """One scene of a campaign."""

    name: str                     # output subfolder, the scene file's stem
    path: Path
    overrides: tuple[str, ...]
    gates: tuple[Gate, ...] = ()  # the scene's own, the campaign's and the command line's


@dataclass(frozen=True)
class Campaign:
    title: str
    description: str
    entries: tuple[Entry, ...]
    quick: bool
    path: Path


def is_campaign(path: str | Path) -> bool:
    """True if ``path`` is a campaign file (it has a ``campaign`` list)."""
    return "campaign" in read_toml(Path(path))


def load_campaign(path: str | Path, overrides=(), quick: bool = False,
                  gates: tuple[Gate, ...] = ()) -> Campaign:
    """Read a campaign and validate every scene in it, as it will run (with its gates)."""
    path = Path(path)
    data = read_toml(path)
    for key in data:
        if key not in _TOP_KEYS:
            raise unknown_key(key, list(_TOP_KEYS))
    names = data["campaign"]
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise InputError("campaign", f"{names!r} is not a list of scenes; allowed: "
                         'campaign = ["table1", "fig8", ...] (names in scenes/ or .toml paths)')
    flag = data.get("quick", False)
    if not isinstance(flag, bool):
        raise InputError("quick", f"{flag!r} is not a boolean; allowed: true or false")
    per_scene = data.get("overrides", {})
    if not isinstance(per_scene, dict):
        raise InputError("overrides", "must be a table: <scene> = [\"key=value\", ...]")
    entries = [Entry(name=_scene_path(path, n).stem, path=_scene_path(path, n),
                     overrides=tuple(per_scene.get(_scene_path(path, n).stem, ())) + tuple(overrides))
               for n in names]
    stems = [e.name for e in entries]
    for name, sets in per_scene.items():
        if name not in stems:
            raise InputError(f"overrides.{name}", f"names no scene of this campaign; allowed: {', '.join(stems)}")
        if not isinstance(sets, list) or not all(isinstance(s, str) for s in sets):
            raise InputError(f"overrides.{name}", f"{sets!r} is not a list of \"key=value\" strings")
    if len(set(stems)) != len(stems):
        raise InputError("campaign", f"lists a scene twice ({', '.join(stems)}); each needs its own folder")
    per_scene_gates = data.get("gates", {})
    if not isinstance(per_scene_gates, dict):
        raise InputError("gates", "must be tables: [gates.<scene>] \"dotted.path\" = { max = X }")
    for name in per_scene_gates:
        if name not in stems:
            raise InputError(f"gates.{name}", f"names no scene of this campaign; allowed: {', '.join(stems)}")
    quick = quick or flag
    checked = []
    for entry in entries:
        try:
            scene = load_scene(entry.path, list(entry.overrides), quick=quick)
            own = from_table(per_scene_gates.get(entry.name, {}), f"gates.{entry.name}")
            entry = replace(entry, gates=merged(scene.gates, own, tuple(gates)))
        except InputError as exc:
            raise InputError(f"{entry.name}: {exc.key}", exc.message) from None
        if not scene.study:
            raise InputError(f"{entry.name}: study", "the scene names no study")
        checked.append(entry)
    entries = checked
    return Campaign(title=str(data.get("title", path.stem)), description=str(data.get("description", "")),
                    entries=tuple(entries), quick=quick, path=path)


def _scene_path(campaign_path: Path, name: str) -> Path:
    """``name`` as a scene file: a .toml path (relative to the campaign file), or scenes/<name>.toml."""
    if not isinstance(name, str) or not name:
        raise InputError("campaign", f"{name!r} is not a scene name")
    candidate = Path(name if name.endswith(".toml") else f"{name}.toml")
    for base in (campaign_path.parent, Path.cwd(), Path.cwd() / "scenes"):
        full = candidate if candidate.is_absolute() else base / candidate
        if full.is_file():
            return full
    raise InputError("campaign", f"no scene {name!r} (looked for {candidate} next to {campaign_path} "
                     "and in scenes/)")


def _run_entry(task: tuple[str, str, tuple[str, ...], bool, tuple[Gate, ...]]) -> dict:
    """Run one scene of a campaign; a failure is recorded, not raised."""
    path, out, overrides, quick, gates = task
    t0 = time.perf_counter()
    try:
        return run_scene(path, out=out, overrides=overrides, quick=quick, writer=True, gates=gates)
    except Exception as exc:      # noqa: BLE001 - one scene's failure must not stop the others
        warn(f"scene {path} failed: {type(exc).__name__}: {exc}")
        Path(out).mkdir(parents=True, exist_ok=True)
        write_text(Path(out) / "error.txt", traceback.format_exc())
        return {"status": f"failed ({type(exc).__name__}: {exc})", "out": out,
                "elapsed_s": round(time.perf_counter() - t0, 3)}


def run_campaign(path: str | Path, out: str | Path | None = None, overrides=(), quick: bool = False,
                 gates: tuple[Gate, ...] = ()) -> dict:
    """Validate then run every scene of campaign ``path``; write ``out/report.md``.

    ``gates`` (the command line's) reach every scene. The summary's ``gates``
    lists every scene's gate records, each with its ``scene``.
    """
    campaign = load_campaign(path, overrides, quick, gates)
    out = output_folder(path, out)
    writer = mpi_rank() == 0
    with holding(out, writer):
        return _run_entries(campaign, path, out, writer)


def _run_entries(campaign: Campaign, path, out: Path, writer: bool) -> dict:
    size = mpi_size()
    spread = f"{size} MPI ranks" if size > 1 else f"{min(workers(), len(campaign.entries))} local process(es)"
    info(f"campaign {path}: {len(campaign.entries)} scenes{' (quick)' if campaign.quick else ''} "
         f"over {spread} -> {out}")
    tasks = [(str(e.path), str(out / e.name), e.overrides, campaign.quick, e.gates) for e in campaign.entries]
    t0 = time.perf_counter()
    status = "complete"
    outcomes: list[SceneOutcome] = []
    try:
        map_parallel(_run_entry, tasks)
    except KeyboardInterrupt:
        status = "partial (interrupted)"
        raise
    finally:
        elapsed = time.perf_counter() - t0
        if writer:
            with shielded_from_interrupts():     # a repeated Ctrl-C must not cut the summary
                outcomes = [_outcome(e, out / e.name) for e in campaign.entries]
                if any(o.status != "complete" for o in outcomes) and status == "complete":
                    status = "complete with failures"
                _write_campaign(out, campaign, outcomes, status, elapsed, spread)
    info(f"campaign done in {seconds(elapsed)}: {out / 'report.md'}")
    return {"campaign": campaign.title, "out": str(out), "status": status, "elapsed_s": round(elapsed, 3),
            "gates": [{"scene": o.name, **r} for o in outcomes for r in o.gates]}


def _outcome(entry: Entry, folder: Path) -> SceneOutcome:
    """What the scene's own results.json says (or that it never ran: its gates then fail)."""
    try:
        record = json.loads((folder / "results.json").read_text())
    except (FileNotFoundError, json.JSONDecodeError):
        return SceneOutcome(entry.name, "?", entry.name, "not run", None, folder,
                            tuple(hold(entry.gates, {"status": "not run"})))
    return SceneOutcome(entry.name, record.get("study", "?"), record.get("title", entry.name),
                        record.get("status", "?"), record.get("elapsed_s"), folder,
                        tuple(record.get("gates", ())))


def _write_campaign(out: Path, campaign: Campaign, outcomes: list[SceneOutcome], status: str,
                    elapsed: float, spread: str) -> None:
    preamble = campaign_gate_summary(outcomes) + (
        f"{campaign.description}\n\n" if campaign.description else "") + (
        f"Campaign `{campaign.path}`{' (quick versions)' if campaign.quick else ''}: "
        f"{len(outcomes)} scenes over {spread}, {status}, wall time {seconds(elapsed)}.\n\n")
    stitch(out, campaign.title, outcomes, preamble)
    payload = {"campaign": campaign.title, "file": str(campaign.path), "status": status,
               "quick": campaign.quick, "elapsed_s": round(elapsed, 3), "spread": spread,
               "versions": versions(),
               "scenes": [{"name": o.name, "study": o.study, "status": o.status,
                           "elapsed_s": o.elapsed_s, "results": f"{o.name}/results.json",
                           "gates": {"held": sum(r["passed"] for r in o.gates),
                                     "failed": sum(not r["passed"] for r in o.gates)}}
                          for o in outcomes]}
    write_text(out / "results.json", json.dumps(jsonable(payload), indent=1))
    gated = [(o.name, junit.gate_cases(o.gates)) for o in outcomes if o.gates]
    if gated:
        junit.write(out / "junit.xml", f"shroud gates: {campaign.title}", gated)
    else:
        (out / "junit.xml").unlink(missing_ok=True)
