"""Sweep cost: time of one sweep cell per processed frame, split into its stages.

A cell frame = scatterers (ray RCS) + 2 ADC simulations (DDMA, TDMA) + 3 chain runs (DDMA,
TDMA, TDMA raw); the cell then associates and scores the whole run and tracks each scheme.
The floor is the stage sum measured in the same run, so "overhead" is what the harness adds
(association, metrics, tracking, table building).
"""
from __future__ import annotations

from benchmarks._timing import median_time_s

CASE = "r79_motorcycle_rear"
DURATION_S = 1.0


def run() -> list[str]:
    import pipeline
    from harness.cell.components import default_components
    from harness.cell.config import build_configs
    from harness.cell.run import frame_scatterers, run_cell
    from harness.cell.spec import CellSpec, result_schemes
    from harness.sweep.streams import frame_rng

    comps = default_components()
    spec = CellSpec(scenario=CASE, duration_s=DURATION_S)
    run_ = comps.run_scenario(CASE, 0, DURATION_S)
    radar, procs = build_configs(spec, comps)
    frame = int(run_.ego["frame"].iloc[len(run_.ego) // 2])
    sc = frame_scatterers(comps, run_, frame, 0)
    adc = {m: comps.simulate_frame(radar[m], sc, frame_rng(0, frame, m)) for m in radar}
    t_sc = median_time_s(lambda: frame_scatterers(comps, run_, frame, 0), 5, 1)
    t_sim = sum(median_time_s(lambda m=m: comps.simulate_frame(radar[m], sc,
                                                               frame_rng(0, frame, m)), 5, 1)
                for m in radar)
    t_proc = sum(median_time_s(lambda s=s, m=m: pipeline.process_frame(radar[m], adc[m],
                                                                        procs[s]), 5, 1)
                 for s, m in ((rs.name, rs.mimo) for rs in result_schemes(spec.schemes)))
    t_cell = median_time_s(lambda: run_cell(spec, comps), 3, 1)
    n = len(run_.ego)
    floor = t_sc + t_sim + t_proc
    per_frame = t_cell / n
    lines = [
        f"sweep cell {CASE} ({n} frames): {t_cell:.2f} s median, {1e3 * per_frame:.0f} ms/frame",
        f"  stages per frame: scatterers {1e3 * t_sc:.0f} ms, 2 ADC sims {1e3 * t_sim:.0f} ms, "
        f"3 chain runs {1e3 * t_proc:.0f} ms (floor {1e3 * floor:.0f} ms)",
        f"  harness overhead (scenario, association, metrics, tracker): "
        f"{per_frame / floor:.2f}x the stage floor",
    ]
    return lines + _ghosts_versus_phase_error(comps)


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
