"""[TI-DDMA] section 4.2 (figures 7-8): phase-shifter errors before / after calibration.

One Tx stepped by 90 deg per chirp, a static 10 m^2 corner reflector at 4.5 m boresight
(`harness.shifter_experiment`). For an uncalibrated per-code table of about +/-10 deg
(a vector-modulator shifter with 20 deg quadrature skew plus 1 deg DNL; then a random
`inl_dnl` table, 6 deg rms, seed 0) the bench prints the lines of the range-Doppler cut at the
reflector's range (target, mirror ghost, DC and Nyquist spurs) in dBc, measured on the
simulated ADC frame and predicted by the DFT of the code period's complex weights, before and
after `calibrate_shifters`, and writes the cut to `results/bench_shifter_fig7_8.png`. Then a
Monte-Carlo over 100 tables gives the spread of the mirror-ghost drop and the worst
measured-minus-predicted line; the same for a vector-modulator shifter with a 20 deg quadrature
skew (+/-10 deg about its mean, plus 1 deg DNL), with its gain error and without it
(`vm_phase_only`): nearest-phase calibration cannot correct the gain of the chosen codes.
Timings: `calibrate_shifters`, `transmit_phasors` and `simulate_frame` with error tables, as
ratios to the same calls without them (same run).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import radarsim
from benchmarks._timing import median_time_s
from harness.shifter_experiment import format_lines, phase_step_experiment, plot_phase_step
from radarsim import shifter as sh

N_CHIRPS = 1024
#: Lines are compared with the prediction when this far above the noise floor of the cut, dB
#: (a line 20 dB above the floor is off by at most 20 log10(1 + 10^-1) = 0.83 dB).
MARGIN_DB = 20.0
FIGURE = Path("results") / "bench_shifter_fig7_8.png"


def _pair(cfg, seed: int):
    """(before, after, calibration result) of the 90-deg experiment on one radar."""
    cal = radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(seed), full_output=True)
    before = phase_step_experiment(cfg, rng=np.random.default_rng(seed + 1), n_chirps=N_CHIRPS)
    after = phase_step_experiment(cal.config, rng=np.random.default_rng(seed + 1),
                                  n_chirps=N_CHIRPS)
    return before, after, cal


def _mirror(res, col: str) -> float:
    return float(res.lines.loc[res.lines["role"] == "mirror ghost", col].item())


def _floor_dbc(res) -> float:
    """Noise floor of the cut: median bin, dBc."""
    return float(np.median(res.cut_dbc))


def _max_line_error(res) -> float:
    """Worst |measured - predicted| over lines predicted MARGIN_DB above the noise floor."""
    ok = res.lines["predicted_dbc"] > _floor_dbc(res) + MARGIN_DB
    return float(np.max(np.abs(res.lines["measured_dbc"] - res.lines["predicted_dbc"])[ok]))


def _tables(kind: str, seed: int):
    if kind == "inl_dnl":
        return ({"distribution": "inl_dnl", "rms": 6.0, "seed": seed},
                {"distribution": "inl_dnl", "rms": 0.1, "seed": 1000 + seed})
    e, g = sh.vector_modulator_tables(64, 20.0, 0.0)
    dnl = sh.ShifterErrorSpec(distribution="gaussian", rms=1.0, seed=seed).draw(4, 64)
    gain = np.tile(g, (4, 1)) if kind == "vector_modulator" else None
    return np.tile(e, (4, 1)) + dnl, gain


def _monte_carlo(kind: str, n: int) -> list[str]:
    drop, err, after_gap, before_m, after_m, floors = [], [], [], [], [], []
    for seed in range(n):
        ph, gn = _tables(kind, seed)
        cfg = radarsim.presets.r79_ddma(shifter={"phase_quantization": "round",
                                                 "shifter_phase_error_deg": ph,
                                                 "shifter_gain_error_db": gn})
        b, a, _ = _pair(cfg, seed)
        before_m.append(_mirror(b, "measured_dbc"))
        after_m.append(_mirror(a, "measured_dbc"))
        drop.append(before_m[-1] - after_m[-1])
        err.append(max(_max_line_error(b), _max_line_error(a)))
        if _mirror(a, "predicted_dbc") > _floor_dbc(a) + MARGIN_DB:
            after_gap.append(_mirror(a, "measured_dbc") - _mirror(a, "predicted_dbc"))
        floors.append(_floor_dbc(a))
    drop = np.array(drop)
    q = lambda x: "/".join(f"{v:.1f}" for v in np.percentile(x, [10, 50, 90]))  # noqa: E731
    return [f"  {kind:<16s} {n} tables: mirror before {q(before_m)} dBc, after {q(after_m)} "
            f"dBc (p10/p50/p90); drop {q(drop)} dB, > 20 dB in {np.mean(drop > 20):.0%}",
            f"  {'':<16s} worst |measured - predicted| over lines {MARGIN_DB:.0f} dB above the "
            f"floor ({np.median(floors):.1f} dBc): {max(err):.2f} dB; calibrated mirror minus "
            f"residual-table prediction {min(after_gap):+.2f}..{max(after_gap):+.2f} dB "
            f"({len(after_gap)} of {n} above the floor + {MARGIN_DB:.0f} dB)"]


def _headline(kind: str, title: str, figure: Path | None) -> tuple[list[str], object]:
    ph, gn = _tables(kind, 0)
    cfg = radarsim.presets.r79_ddma(shifter={"phase_quantization": "round",
                                             "shifter_phase_error_deg": ph,
                                             "shifter_gain_error_db": gn})
    e = np.asarray(cfg.shifter_phase_error_deg)
    before, after, cal = _pair(cfg, 0)
    lines = [f"-- {title}: Tx1 phase error {e[0].min():+.1f}..{e[0].max():+.1f} deg "
             f"(rms {np.sqrt(np.mean(e[0] ** 2)):.1f}), gain error rms "
             f"{np.sqrt(np.mean(np.square(cfg.shifter_gain_error_db))):.2f} dB; reflector "
             f"10 m^2 at 4.5 m, {N_CHIRPS} chirps; calibration SNR {cal.snr_db:.1f} dB/chirp",
             f"   R79 code residual (all Tx): before rms {cal.residual_before_rms_deg:.2f} / max "
             f"{cal.residual_before_max_deg:.2f} deg, after rms {cal.residual_rms_deg:.2f} / "
             f"max {cal.residual_max_deg:.2f} deg"]
    lines += format_lines(before, "before calibration (fig 7)")
    lines += format_lines(after, "after calibration (fig 8)")
    lines.append(f"noise floor of the cut: {_floor_dbc(before):.1f} dBc; mirror ghost "
                 f"{_mirror(before, 'measured_dbc'):.1f} -> {_mirror(after, 'measured_dbc'):.1f}"
                 f" dBc (predicted {_mirror(before, 'predicted_dbc'):.1f} -> "
                 f"{_mirror(after, 'predicted_dbc'):.1f}), drop "
                 f"{_mirror(before, 'measured_dbc') - _mirror(after, 'measured_dbc'):.1f} dB")
    if figure is not None:
        try:
            figure.parent.mkdir(exist_ok=True)
            plot_phase_step(before, after, figure)
            lines.append(f"figure: {figure}")
        except OSError as exc:  # read-only checkout: the numbers above are the record
            lines.append(f"figure not written: {exc}")
    return lines, cfg


def run(repeats: int = 11, warmup: int = 2, n_tables: int = 100) -> list[str]:
    lines, _ = _headline("vm_phase_only", "vector-modulator shifter, 20 deg quadrature skew "
                         "+ 1 deg DNL (seed 0)", FIGURE)
    more, cfg = _headline("inl_dnl", "random INL/DNL table, 6 deg rms (seed 0)", None)
    lines += more
    lines.append("Monte-Carlo over tables (same experiment):")
    lines += _monte_carlo("inl_dnl", n_tables)
    lines += _monte_carlo("vector_modulator", n_tables // 2)
    lines += _monte_carlo("vm_phase_only", n_tables // 2)

    base = radarsim.presets.r79_ddma()
    rng = np.random.default_rng(0)
    t_cal = median_time_s(lambda: radarsim.calibrate_shifters(cfg, rng=rng), repeats, warmup)
    t_w0 = median_time_s(lambda: radarsim.transmit_phasors(base), repeats, warmup)
    t_w1 = median_time_s(lambda: radarsim.transmit_phasors(cfg), repeats, warmup)
    g = np.random.default_rng(1)
    sc = radarsim.Scatterers.from_spherical(g.uniform(5, 200, 100), g.uniform(-70, 70, 100),
                                            g.uniform(-5, 5, 100), g.uniform(-30, 30, 100),
                                            g.uniform(1, 10, 100))
    t_f0 = median_time_s(lambda: radarsim.simulate_frame(base, sc, rng), repeats, warmup)
    t_f1 = median_time_s(lambda: radarsim.simulate_frame(cfg, sc, rng), repeats, warmup)
    lines += [f"calibrate_shifters (4 Tx x 64 codes x 8 chirps): {1e3 * t_cal:.2f} ms",
              f"transmit_phasors with tables / without: {1e3 * t_w1:.3f} / {1e3 * t_w0:.3f} ms",
              f"simulate_frame K=100 with tables / without: {1e3 * t_f1:.2f} / "
              f"{1e3 * t_f0:.2f} ms (ratio {t_f1 / t_f0:.2f})"]
    return lines
