"""Sweep cost: CPU time of one sweep cell per processed frame, against its floor and split into
its stages.

A cell frame = scatterers (ray RCS) + 2 ADC simulations (DDMA, TDMA) + 3 chain runs (DDMA,
TDMA, TDMA raw: one `process_frames` call per ADC frame, so TDMA raw shares TDMA's detections);
the cell then associates and scores the whole run and tracks each scheme.

The cell is timed twice, alternating with its floor (`benchmarks.bench_floors`: two
`simulate_frame` calls with K = 100 point scatterers plus three chain floors, on one core):
with `FRAME_THREADS` frame threads, as a cell runs when a core would otherwise idle (alone,
or among a sweep's last cells), and with one, as a pool sweep runs every other cell
(`harness.cell.run.cell_frame_threads`). Two frames at a time buy wall time with CPU: two
frames' working sets share the cache and the memory bandwidth. The stages are timed on one
thread (`pipeline.threads.inline`, as a cell frame runs them), so "overhead" is what the
harness adds per frame on top of them (scenario, association, metrics, tracking, tables).
"""
from __future__ import annotations

from benchmarks._timing import ROUNDS, alternating_best
from benchmarks.bench_floors import cell_floor

CASE = "r79_motorcycle_rear"
DURATION_S = 1.0


def run() -> list[str]:
    import pipeline
    from harness.cell.components import default_components
    from harness.cell.config import build_configs
    from harness.cell.run import FRAME_THREADS, frame_scatterers, run_cell
    from harness.cell.spec import CellSpec, result_schemes
    from harness.sweep.streams import frame_rng
    from pipeline.threads import inline

    comps = default_components()
    spec = CellSpec(scenario=CASE, duration_s=DURATION_S)
    run_ = comps.run_scenario(CASE, 0, DURATION_S)
    radar, procs = build_configs(spec, comps)
    frame = int(run_.ego["frame"].iloc[len(run_.ego) // 2])
    sc = frame_scatterers(comps, run_, frame, 0)
    adc = {m: comps.simulate_frame(radar[m], sc, frame_rng(0, frame, m)) for m in radar}
    settings: dict[str, list] = {}  # per ADC frame, as the cell asks for its clouds
    for rs in result_schemes(spec.schemes):
        settings.setdefault(rs.mimo, []).append(procs[rs.name])

    def stage(fn):
        def call():
            with inline():
                fn()
        return call

    st = alternating_best({
        "scatterers": stage(lambda: frame_scatterers(comps, run_, frame, 0)),
        "sims": stage(lambda: [comps.simulate_frame(radar[m], sc, frame_rng(0, frame, m))
                               for m in radar]),
        "chains": stage(lambda: [pipeline.process_frames(radar[m], adc[m], ps)
                                 for m, ps in settings.items()])})
    t = alternating_best({"cell": lambda: run_cell(spec, comps, frame_threads=FRAME_THREADS),
                          "cell1": lambda: run_cell(spec, comps, frame_threads=1),
                          "floor": cell_floor()})
    n = len(run_cell(spec, comps).tables["truth"]["frame"].unique())
    fc = t["floor"].cpu_s
    stages = sum(v.cpu_s for v in st.values())

    def cell(label: str, k: str) -> str:
        cpu, wall = t[k].cpu_s / n, t[k].wall_s / n
        return (f"  {label}: {1e3 * cpu:.1f} ms CPU per frame (wall {1e3 * wall:.1f}), "
                f"{cpu / fc:.2f}x the floor")
    return [
        f"sweep cell {CASE} ({n} frames), best of {ROUNDS} alternated with its floor "
        f"(2 `simulate_frame` K = 100 + 3 chain floors, one core): {1e3 * fc:.1f} ms CPU",
        cell(f"{FRAME_THREADS} frame threads (a cell alone, or a sweep's last cells)", "cell"),
        cell("1 frame thread (a pool sweep's other cells)", "cell1"),
        f"  stages per frame, one thread (CPU): scatterers {1e3 * st['scatterers'].cpu_s:.1f} ms"
        f", 2 ADC sims {1e3 * st['sims'].cpu_s:.1f} ms, 3 chain runs "
        f"{1e3 * st['chains'].cpu_s:.1f} ms (sum {1e3 * stages:.1f} ms); harness overhead "
        f"(scenario, association, metrics, tracker) {1e3 * (t['cell1'].cpu_s / n - stages):.1f}"
        " ms per frame on one frame thread",
    ] + _ghosts_versus_phase_error(comps)


def _ghosts_versus_phase_error(comps) -> list[str]:
    """Ghosts per frame and ghost rate on realistic traffic (dense highway, guard rails, 2 s)
    versus the random per-chirp phase error of the transmit chain."""
    from harness.cell.run import run_cell
    from harness.cell.spec import CellSpec

    out = ["ghosts vs random per-chirp phase error, dense_highway 2 s (40 frames):"]
    for err in (0.0, 2.0, 5.0, 10.0, 20.0):
        spec = CellSpec(scenario="dense_highway", duration_s=2.0,
                        radar={"phase_noise_deg_rms": err})
        summary = run_cell(spec, comps).tables["summary"].set_index("scheme")
        row = "  ".join(f"{m}: {summary.loc[m, 'ghosts_per_frame']:.2f}/frame "
                        f"(rate {summary.loc[m, 'ghost_rate']:.3f})" for m in ("ddma", "tdma"))
        out.append(f"  {err:4.1f} deg rms  {row}")
    return out
