"""Interference diagram and Campbell per nodal diameter of the ring's linear limits (issue 26; docs/ring.md).

The tuned ring of ``ring.blades`` = N blades with its interfaces free or
stuck (shroud.analysis.limits: one Bloch sector per nodal diameter n =
0 .. N/2). (a) The interference diagram at the scene's speed: frequency
against n, with the engine orders' excitation f = k rpm / 60, which meets
nodal diameter k mod N (folded to N - (k mod N) above N/2); the engine order
load.ke is the study's. (b) Campbell per nodal diameter: the stuck ring's
lowest family at n = ke mod N over speed, the fixed-neighbour blade stuck
and the free blade, with the line ke rpm / 60: the linear resonances the
ring's travelling wave passes through, against the paper's blade.

Conclusion: where the engine order's nodal diameter puts the stuck ring's
flap family against the blade stuck to fixed neighbours, which has
relative motion factor 1 against the ring's 2 |sin(pi n / N)|.

With ``disk.thickness`` > 0 (the full scene) the cyclic FE sector of blade
and flexible disk (reference_fe.cyclic, docs/disk.md) gives the same
diagram, free and stuck, at the scene's speed, drawn beside the beams' ring
(which keeps the rigid disk), and the same sector with the disk made rigid
(``disk.E_factor`` = RIGID, within 0.11-0.39 % of the clamped blade,
docs/disk.md) splits the beams' ring's difference from it per nodal
diameter k into the beam's own difference from the solid on the rigid disk,
f_ring(k) / f_rigid(k) - 1, and the disk's effect, f_rigid(k) / f_sector(k)
- 1. Where the disk's effect on flap1 exceeds the beam's own difference,
the disk moves the ring more than the beam misses the solid by: the rigid
disk stops holding there (docs/ring.md, docs/disk.md).

The study is compute (:func:`compute` -> :class:`InterferenceComparison`) -> plot -> report.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comparisons._study import study
from shroud.analysis.limits import INTERFACES, interface_modal
from shroud.base.errors import InputError
from shroud.base.markdown import markdown_table
from shroud.base.outputs import open_replacing
from shroud.core.plotting import figure, save
from shroud.core.verdict import NOT_DECIDED, Verdict

RING = True          # solves the ring of ring.blades (workbench.runner refuses a ring elsewhere)
DISK = True          # disk.thickness > 0: the FE sector of blade and disk (workbench.scene lets the disk through)
EIGEN_TOLERANCE = 1e-8   # relative accuracy of the eigen-solves' frequencies (shroud.analysis.limits)
IDENTITY = 1e-6          # an identity of the stuck ring holds to this relative difference (well above 1e-8)
# The error of a rigid-disk verdict's number, |disk effect| - |the beams' ring's own difference| (value - threshold),
# on the P2 3.5 mm sector (meshes.disk's, graded at the rim edge), per interface the larger of nd 0 and 12: its
# distance to the same number of the two sectors' P3 3.5 / 3.0 / 2.7 mm limits plus the limits' own uncertainty
# (`python scripts/disk_checks.py interference`, docs/disk.md, "Beside the beams' ring", "The graded default").
# Not one frequency's error: the flexible sector's flap1 lies 0.25 % (free) and 0.41 % (stuck nd 12) above its
# limit, the rigid-disk one's 0.03-0.05 %, so the two sectors' errors do not cancel in the disk's effect, and the
# rigid one's enters the threshold as well. (On the uniform sector: 0.0046 and 0.0076.)
SECTOR_ERROR = {"free": 0.0034, "stuck": 0.0061}
RIGID = 1000.0       # disk.E_factor of the rigid-disk sector (docs/disk.md, (b): the rigid-disk limit)
SECTOR_MESH = {"fe.cell": "tet", "fe.mesh_size": 0.0035, "fe.order": 2}   # the mesh SECTOR_ERROR was measured for
OPTIONS = {"rpm_from": 2000.0, "rpm_to": 16000.0, "speeds": 29, "n_modes": 3, "engine_orders": 12,
           "model": "reduced"}


def sector_error_words() -> str:
    """SECTOR_ERROR in words, per interface ('free 0.34%, stuck 0.61%')."""
    return ", ".join(f"{i} {e:.2%}" for i, e in SECTOR_ERROR.items())


def check(scene) -> None:
    o, N = scene.options, scene.params.ring.blades
    if N < 2:
        raise InputError("ring.blades", "the interference diagram is a ring's; allowed: ring.blades >= 2")
    if not scene.params.ring.tuned:
        raise InputError("ring.mistuning", "nodal diameters belong to a tuned ring; allowed: all d_j = 0")
    if not 0 < o["rpm_from"] < o["rpm_to"] or o["speeds"] < 2:
        raise InputError("options.rpm_from", "allowed: 0 < rpm_from < rpm_to and speeds >= 2")
    fe = scene.params.fe
    if scene.params.disk.thickness > 0 and (fe.cell, fe.mesh_size, fe.order) != tuple(SECTOR_MESH.values()):
        raise InputError("fe.mesh_size", f"the rigid-disk verdicts' error ({sector_error_words()}) was measured on "
                                         f"{SECTOR_MESH['fe.mesh_size']} m P2 tetrahedra; allowed with a disk: "
                                         + ", ".join(f"{k} = {v!r}" for k, v in SECTOR_MESH.items()))


def folded(k: int, N: int) -> int:
    """The nodal diameter engine order k excites: k mod N, folded into 0 .. N/2."""
    n = k % N
    return min(n, N - n)


def _flap(params, model, rpm, n_modes, interface, coriolis=False):
    """The blade's modes and the ring's per nodal diameter at ``rpm`` (Hz)."""
    limit = interface_modal(params, model, rpm, n_modes, coriolis, interface)
    return ([m.f_hz for m in limit.blade.modes],
            {d["nd"]: [m["f_hz"] for m in d["modes"]] for d in limit.nodal_diameters})


def crossing(rpm: np.ndarray, f: np.ndarray, ke: int) -> float | None:
    """The speed (r/min) where f(rpm) meets ke rpm / 60, linearly interpolated; None if it does not."""
    g = f - ke * rpm / 60.0
    idx = np.flatnonzero(np.sign(g[:-1]) != np.sign(g[1:]))
    if not idx.size:
        return None
    i = idx[0]
    return float(rpm[i] - g[i] * (rpm[i + 1] - rpm[i]) / (g[i + 1] - g[i]))


def meets(rpm: np.ndarray, f: np.ndarray, ke: int, what: str) -> Verdict:
    """Whether the line ke rpm / 60 meets ``f`` (Hz over ``rpm`` r/min) in the range: the smallest ratio
    f / (ke rpm / 60) over the speeds > 0 against 1 (below: they cross), margin the ratio's change over the
    step next to its smallest (where f^2 = f0^2 + S (rpm/60)^2, S < ke^2, the ratio falls with speed: the
    smallest lies at the top speed, on the grid; a dip between two speeds would be bounded by that step)."""
    at = rpm > 0
    ratio = f[at] / (ke * rpm[at] / 60.0)
    i = int(np.argmin(ratio))
    step = max(abs(ratio[j] - ratio[i]) for j in (i - 1, i + 1) if 0 <= j < ratio.size)
    return Verdict.of(float(ratio[i]), threshold=1.0, margin=float(step), below=True, above=False,
                      reason=f"smallest {what} / (k_e x rotation) over {rpm[at][0]:g}-{rpm[-1]:g} r/min against 1, "
                             "margin its change over the speed step next to it")


@dataclass(frozen=True)
class InterferenceComparison:
    """The ring's frequencies per nodal diameter at the scene's speed and its flap family over speed."""

    N: int                        # blades
    ke: int                       # engine order load.ke
    model: str
    rpm: float                    # the diagram's speed, r/min
    n_modes: int                  # modes per nodal diameter
    engine_orders: int            # engine-order lines drawn: 0 .. engine_orders
    diagram: dict[str, dict[int, list[float]]]   # "free"/"stuck" -> nd -> frequencies (Hz)
    blade_free_hz: list[float]    # the free blade's modes at rpm (Hz)
    fixed_stuck_hz: float         # flap1 of the blade stuck to fixed neighbours at rpm (Hz)
    rpms: np.ndarray              # the Campbell speeds, r/min
    ring_nd: np.ndarray           # the stuck ring's flap1 at the engine order's nodal diameter (Hz)
    blade_fixed: np.ndarray       # the blade stuck to fixed neighbours (Hz)
    blade_free: np.ndarray        # the free blade (Hz)
    disk_thickness: float = 0.0   # disk.thickness (m); > 0: the FE sector below was solved
    sector: dict[str, dict[int, list[float]]] | None = None   # the FE sector of blade and disk, as ``diagram``
    rigid: dict[str, dict[int, list[float]]] | None = None    # the same sector, its disk's E x RIGID

    def beam_difference(self, interface: str) -> dict[int, float]:
        """Per nodal diameter the beams' ring's flap1 over the rigid-disk sector's, less 1: the beam's own
        difference from the solid with the disk the beams have."""
        ring, rigid = self.diagram[interface], self.rigid[interface]
        return {n: ring[n][0] / rigid[n][0] - 1.0 for n in sorted(rigid)}

    def disk_effect(self, interface: str) -> dict[int, float]:
        """Per nodal diameter the rigid-disk sector's flap1 over the flexible one's, less 1: the disk's effect."""
        rigid, sector = self.rigid[interface], self.sector[interface]
        return {n: rigid[n][0] / sector[n][0] - 1.0 for n in sorted(sector)}

    def rigid_disk(self, interface: str, n: int) -> Verdict:
        """Whether the rigid disk holds for flap1 at nodal diameter n: the disk's effect against the beam's own
        difference from the solid there, margin the measured error of the two's difference on this mesh
        (SECTOR_ERROR: both sides come from the sectors, within it the disk is not seen)."""
        d = self.beam_difference(interface)[n]
        return Verdict.of(abs(self.disk_effect(interface)[n]), threshold=abs(d), margin=SECTOR_ERROR[interface],
                          below=True, above=False,
                          reason=f"|disk effect| on the {interface} flap1 at nd {n} (the FE sector with its disk's E x "
                                 f"{RIGID:g} over the sector with the {self.disk_thickness:g} m disk, less 1) against "
                                 f"the beams' ring's own difference from the rigid-disk sector there ({d:+.3%}); "
                                 f"margin the measured error of value - threshold on the sectors' mesh, "
                                 f"{SECTOR_ERROR[interface]:.2%} (against their P3 limits and the rigid-disk "
                                 "limit, nd 0 and 12; docs/disk.md)")

    def rigid_disk_answers(self, interface: str) -> dict[str, list[int]]:
        """The nodal diameters by answer of :meth:`rigid_disk` ("holds", "disk matters", "not decided")."""
        out: dict[str, list[int]] = {"holds": [], "disk matters": [], NOT_DECIDED: []}
        for n in sorted(self.sector[interface]):
            a = self.rigid_disk(interface, n).answer
            out["holds" if a is True else "disk matters" if a is False else NOT_DECIDED].append(n)
        return out

    @property
    def nd_ke(self) -> int:
        return folded(self.ke, self.N)

    @property
    def factor(self) -> float:
        """The relative-motion factor 2 |sin(pi n / N)| at the engine order's nodal diameter."""
        return 2 * abs(math.sin(math.pi * self.nd_ke / self.N))

    @property
    def crossings(self) -> dict[str, float | None]:
        return {"ring_stuck": crossing(self.rpms, self.ring_nd, self.ke),
                "fixed_neighbours_stuck": crossing(self.rpms, self.blade_fixed, self.ke),
                "free": crossing(self.rpms, self.blade_free, self.ke)}

    def verdicts(self) -> dict[str, Verdict]:
        """The ring's flap1 at the engine order's nodal diameter against the blade stuck to fixed neighbours;
        two identities of the stuck ring (nd 0: no relative motion, the free blade; nd N/4: neighbours in
        quadrature, |1 - exp(i pi / 2)|^2 = 2 = the two fixed interfaces' 1 + 1, the blade stuck to fixed
        neighbours); whether the engine order's line meets the stuck ring's and the free blade's flap1 in
        the speed range (the interference diagram's crossings)."""
        nd, stuck = self.nd_ke, self.diagram["stuck"]
        out = {"ring_against_fixed_neighbours": Verdict.of(
            float(stuck[nd][0] / self.fixed_stuck_hz), threshold=1.0, margin=EIGEN_TOLERANCE,
            below="ring softer", above="ring stiffer",
            reason=f"stuck flap1 of the ring at nd {nd} over the blade stuck to fixed neighbours at {self.rpm:g} "
                   f"r/min (relative-motion factor {self.factor:.3f} against 1; margin the eigen-solves' relative "
                   f"accuracy {EIGEN_TOLERANCE:g})"),
            "stuck_nd0_is_free_blade": Verdict.of(
                max(abs(s / f - 1.0) for s, f in zip(stuck[0], self.diagram["free"][0])),
                threshold=IDENTITY, margin=EIGEN_TOLERANCE, below=True, above=False,
                reason="largest relative difference of the stuck ring's modes at nd 0 from the free ring's: at nd 0 "
                       "neighbours move alike (2 |sin 0| = 0), the stuck interface carries no load; threshold "
                       f"{IDENTITY:g}, margin the eigen-solves' accuracy")}
        if self.N % 4 == 0:
            out["stuck_quarter_nd_is_fixed_neighbours"] = Verdict.of(
                abs(stuck[self.N // 4][0] / self.fixed_stuck_hz - 1.0), threshold=IDENTITY, margin=EIGEN_TOLERANCE,
                below=True, above=False,
                reason=f"relative difference of the stuck ring's flap1 at nd {self.N // 4} = N/4 from the blade "
                       "stuck to fixed neighbours: in quadrature |1 - exp(i pi / 2)|^2 = 2, the two fixed "
                       f"interfaces' 1 + 1; threshold {IDENTITY:g}, margin the eigen-solves' accuracy")
        for name, f_hz, what in (("engine_order_meets_stuck_ring", self.ring_nd, f"the stuck ring's flap1 at nd {nd}"),
                                 ("engine_order_meets_free_blade", self.blade_free, "the free blade's flap1")):
            out[name] = meets(self.rpms, f_hz, self.ke, what)
        for iface in INTERFACES if self.sector is not None else ():   # where the disk moves flap1 most
            effect = self.disk_effect(iface)
            out[f"rigid_disk_holds_{iface}"] = self.rigid_disk(iface, max(effect, key=lambda m: abs(effect[m])))
        return out

    def conclusions(self) -> dict:
        return {name: v.to_json() for name, v in self.verdicts().items()}

    def to_json(self) -> dict:
        i = int(np.argmin(abs(self.rpms - self.rpm)))
        nds = sorted(self.diagram["stuck"])
        return {"conclusions": self.conclusions(), "nd_engine_order": self.nd_ke,
                "relative_motion_factor": self.factor,
                "flap1_hz": {"ring_stuck": self.diagram["stuck"][self.nd_ke][0],
                             "fixed_neighbours_stuck": self.fixed_stuck_hz, "free": self.blade_free_hz[0]},
                "crossing_rpm": self.crossings, "ratio_on_grid": float(self.ring_nd[i] / self.blade_fixed[i]),
                "nodal_diameters": {iface: {str(n): self.diagram[iface][n] for n in nds}
                                    for iface in INTERFACES}, **self._sector_json()}

    def _sector_json(self) -> dict:
        if self.sector is None:
            return {}
        per_nd = {"nodal_diameters": self.sector, "rigid_disk_nodal_diameters": self.rigid}
        return {"fe_sector": {"disk_thickness_m": self.disk_thickness, "rigid_E_factor": RIGID,
                              **{key: {iface: {str(n): f for n, f in d[iface].items()} for iface in INTERFACES}
                                 for key, d in per_nd.items()},
                              **{key: {iface: {str(n): e for n, e in f(iface).items()} for iface in INTERFACES}
                                 for key, f in (("beam_difference", self.beam_difference),
                                                ("disk_effect", self.disk_effect))},
                              "rigid_disk_nd": {iface: self.rigid_disk_answers(iface) for iface in INTERFACES}}}


def compute(scene) -> InterferenceComparison:
    """The free and stuck ring per nodal diameter at the scene's speed; the flap family over the speeds."""
    params, o = scene.params, scene.options
    N, ke, model, k = params.ring.blades, params.load.ke, o["model"], o["n_modes"]
    nd_ke = folded(ke, N)
    rpm0, disk = params.speed.rpm, params.disk.thickness
    sector = rigid = None
    if disk > 0:      # the FE sector of blade and disk, flexible and rigid (without Coriolis, as the beams' ring)
        sector, rigid = ({iface: _flap(p, "fe", rpm0, k, iface)[1] for iface in INTERFACES}
                         for p in (params, params.updated({"disk.E_factor": RIGID * params.disk.E_factor})))
        params = params.updated({"disk.thickness": 0.0})     # the beams' ring: the rigid disk
    fixed_params = params.updated({"ring.blades": 0})
    free, diagram_free = _flap(params, model, rpm0, k, "free")
    _, diagram_stuck = _flap(params, model, rpm0, k, "stuck")
    fixed_stuck = interface_modal(fixed_params, model, rpm0, k, False, "stuck")
    rpms = np.linspace(o["rpm_from"], o["rpm_to"], o["speeds"])
    ring_nd, blade_free, blade_fixed = [], [], []
    for r in rpms:
        free_r, _ = _flap(params, model, r, 1, "free")
        _, stuck = _flap(params, model, r, 1, "stuck")
        fixed = interface_modal(fixed_params, model, r, 1, False, "stuck")
        ring_nd.append(stuck[nd_ke][0])
        blade_free.append(free_r[0])
        blade_fixed.append(fixed.blade.modes[0].f_hz)
    return InterferenceComparison(N=N, ke=ke, model=model, rpm=rpm0, n_modes=k, engine_orders=o["engine_orders"],
                                  diagram={"free": diagram_free, "stuck": diagram_stuck}, blade_free_hz=free,
                                  fixed_stuck_hz=fixed_stuck.blade.modes[0].f_hz, rpms=rpms,
                                  ring_nd=np.array(ring_nd), blade_free=np.array(blade_free),
                                  blade_fixed=np.array(blade_fixed), disk_thickness=disk, sector=sector,
                                  rigid=rigid)


def plot(result: InterferenceComparison, scene, out: Path) -> list[str]:
    """(a) the interference diagram, (b) the flap family over speed (interference.png); the diagram as CSV."""
    N, ke, k, rpm0, rpms, nd_ke = result.N, result.ke, result.n_modes, result.rpm, result.rpms, result.nd_ke
    fig, axes = figure(1, 2, width=9.0, height=3.6 if result.sector is None else 4.6)
    ax = axes[0][0]
    nds = sorted(result.diagram["stuck"])
    for iface, style in (("free", ":"), ("stuck", "-")):
        per_nd = result.diagram[iface]
        for i in range(k):
            ax.plot(nds, [per_nd[n][i] for n in nds], style + "o", ms=3, color=f"C{i}",
                    label=f"{'' if result.sector is None else 'beams, '}mode {i + 1}, {iface}")
    if result.sector is not None:     # the FE sector of blade and disk beside the beams' ring (rigid disk)
        for iface, marker in (("free", "x"), ("stuck", "+")):
            per_nd = result.sector[iface]
            for i in range(k):
                ax.plot(nds, [per_nd[n][i] for n in nds], "-" + marker, lw=0.5, ms=4, color=f"C{i}", alpha=0.7,
                        label=f"FE sector, disk {result.disk_thickness:g} m, {iface}" if i == 0 else None)
    orders = np.arange(0, result.engine_orders + 1)
    ax.plot([folded(int(q), N) for q in orders], orders * rpm0 / 60.0, "k--", lw=0.8, label="engine orders")
    ax.plot([nd_ke], [ke * rpm0 / 60.0], "ks", ms=6, mfc="none", label=f"k_e = {ke}")
    ax.set_xlabel("nodal diameter")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"(a) interference diagram, {N} blades, {rpm0:g} r/min")
    if result.sector is None:
        ax.legend(fontsize=6, ncol=2)
    else:         # the sector's curves fill the upper left: the legend goes below the panel
        ax.legend(fontsize=6, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.16))
    ax = axes[0][1]
    ax.plot(rpms, result.ring_nd, "-", label=f"ring stuck, nd {nd_ke}")
    ax.plot(rpms, result.blade_fixed, "--", label="blade stuck to fixed neighbours")
    ax.plot(rpms, result.blade_free, ":", label="free blade")
    ax.plot(rpms, ke * rpms / 60.0, "k-", lw=0.8, label=f"{ke} x rotation")
    ax.set_xlabel("speed (r/min)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title("(b) flap family at the engine order's nodal diameter")
    ax.legend(fontsize=6)
    save(fig, out / "interference.png")
    with open_replacing(out / "interference.csv") as fh:
        w = csv.writer(fh)
        w.writerow(["interface", "nd"] + [f"f{i + 1}_hz" for i in range(k)])
        for source, diagram in (("beams", result.diagram), ("fe_sector", result.sector)):
            for iface in INTERFACES if diagram is not None else ():
                for n in nds:
                    w.writerow([iface if source == "beams" else f"{iface} {source}", n, *diagram[iface][n]])
    return ["interference.png"]


def report(result: InterferenceComparison, scene, files: list[str]) -> str:
    N, ke, nd_ke, rpm0, verdicts = result.N, result.ke, result.nd_ke, result.rpm, result.verdicts()
    rows = [(name, "none in range" if c is None else f"{c:.0f}") for name, c in result.crossings.items()]
    lines = [f"# {scene.title}\n",
             f"{N} blades, engine order {ke} (nodal diameter {nd_ke}, inter-blade phase "
             f"{360.0 * ke / N:g} deg, relative-motion factor 2 |sin(pi n / N)| = {result.factor:.3f}), model "
             f"{result.model}.\n",
             f"At {rpm0:g} r/min the stuck ring's flap1 at nd {nd_ke} is "
             f"{result.diagram['stuck'][nd_ke][0]:.1f} Hz against {result.fixed_stuck_hz:.1f} Hz for the "
             f"blade stuck to fixed neighbours and {result.blade_free_hz[0]:.1f} Hz free.\n",
             markdown_table(["flap1 meets k_e x rotation", "r/min"], rows), ""]
    if result.sector is not None:
        lines += _sector_report(result)
    lines += ["## Verdicts\n"]
    lines += [f"- `{name}`: {v.sentence()}" for name, v in verdicts.items()] + [""]
    lines += [f"![{f}]({f})" for f in files]
    return "\n".join(lines) + "\n"


def _sector_report(result: InterferenceComparison) -> list[str]:
    """The beams' ring (rigid disk) against the FE sector of blade and disk, flap1 per nodal diameter."""
    ring, rigid, sector = result.diagram, result.rigid, result.sector
    beam = {iface: result.beam_difference(iface) for iface in INTERFACES}
    disk = {iface: result.disk_effect(iface) for iface in INTERFACES}
    rows = [(n, *(f"{ring[i][n][0]:.2f} / {rigid[i][n][0]:.2f} / {sector[i][n][0]:.2f} ({beam[i][n]:+.2%}; "
                  f"{disk[i][n]:+.2%})" for i in INTERFACES)) for n in sorted(sector["free"])]
    lines = [f"## Beside the FE sector of blade and disk (disk {result.disk_thickness:g} m)\n",
             f"Flap1 at {result.rpm:g} r/min (Hz): the beams' ring ({result.model}, rigid disk) / the FE sector "
             f"with its disk's E x {RIGID:g} (the rigid disk) / the FE sector; in brackets the beam's own "
             "difference (the ring over the rigid-disk sector, less 1) and the disk's effect (the rigid-disk "
             "sector over the flexible one, less 1). The rigid disk stops holding for the beams' ring where the "
             "disk's effect exceeds the beam's own difference by more than the measured error of that difference "
             f"on the sectors' mesh ({sector_error_words()}; against the sectors' P3 limits, docs/disk.md); "
             "\"holds\" says the disk moves flap1 less than the beams' ring already misses the solid by there, "
             "not that the ring is near the sector.\n",
             markdown_table(["nd"] + [f"flap1 {i}" for i in INTERFACES], rows), ""]
    for iface in INTERFACES:
        answers = result.rigid_disk_answers(iface)
        lines.append(f"- {iface}: " + "; ".join(f"{answer} at nd {', '.join(map(str, nds))}"
                                                for answer, nds in answers.items() if nds))
    return lines + [""]


run = study(compute, plot, report)
