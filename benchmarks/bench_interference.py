"""Interference synthesis and the chirp-level chain: cost and what they do.

Targets: synthesising 10 interferers costs at most 1x `simulate_frame`'s own time for K = 100
scatterers; the chirp-level chain (DC removal, interference statistics and zeroing, EGE
compression) adds at most 30 % to `process_frame` (R79 DDMA). Both are ratios measured in the
same run. The bench also prints the noise-floor rise of one interferer with mitigation off and
on, the range stage's time with each repair method (`pipeline.interference.MITIGATIONS`)
on the 10-interferer frame with where the default ("lowrank") spends it, where the
10-interferer DDMA frame of `benchmarks.bench_floors` (the target "<= 1.3x the clean frame"
row) spends what the clean frame does not (`dirty_frame_breakdown`), and the SNR loss EGE
compression causes a weak target in the same block as a strong one.
"""
from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

import pipeline
import radarsim
from benchmarks._timing import median_time_s
from pipeline import chirp_level as cl
from pipeline.chirp_level.stage import blockwise_range_stage, chirp_statistics
from pipeline.config import WINDOWS
from pipeline.interference import MITIGATIONS, FrameRows, repaired_rows
from pipeline.interference.lowrank import FastTimeBasis, fast_time_basis, lowrank_fill
from pipeline.interference.masks import reference_rows
from pipeline.interference.residual import with_weak_bursts
from pipeline.kernels import window
from pipeline.threads import inline
from radarsim import interference as itf_mod

N_SCATTERERS = 100
N_INTERFERERS = 10
CHAIN_OFF = {"range.dc_removal": False, "interference.repair": "off",
             "compression.enabled": False}


def _scene(k: int, seed: int = 0) -> radarsim.Scatterers:
    g = np.random.default_rng(seed)
    return radarsim.Scatterers.from_spherical(g.uniform(5.0, 200.0, k), g.uniform(-70.0, 70.0, k),
                                              g.uniform(-5.0, 5.0, k),
                                              g.uniform(-30.0, 30.0, k), g.uniform(1.0, 10.0, k))


def interferers(n: int, seed: int = 1) -> itf_mod.Interferers:
    """n radars 10-150 m away, +/-60 deg, waveforms spread over the corner/front families."""
    g = np.random.default_rng(seed)
    r, az = g.uniform(10, 150, n), np.radians(g.uniform(-60, 60, n))
    slope = g.choice([-1, 1], n) * g.uniform(8e12, 50e12, n)
    period = g.uniform(20e-6, 60e-6, n)
    return itf_mod.Interferers(
        position_m=np.column_stack([r * np.cos(az), r * np.sin(az), np.zeros(n)]),
        radial_velocity_mps=g.uniform(-30, 30, n), tx_gain_dbi=np.full(n, 10.0),
        start_freq_hz=g.uniform(76.9e9, 77.1e9, n) + np.where(slope < 0, 0.5e9, 0.0),
        slope_hz_per_s=slope, chirp_period_s=period, ramp_time_s=0.75 * period,
        chirp_offset_s=g.uniform(0, 20e-6, n), tx_power_dbm=np.full(n, 12.0))


def _weak_next_to_strong(diff_db: float, n_c: int = 256, sigma: float = 8.0) -> tuple:
    """(block scale factor median, SNR loss dB, model loss dB) of a weak target 10 sigma above
    the noise in the same EGE block as a strong one `diff_db` above it (three-bin Hann main
    lobe); the model 10 log10(1 + mean(4^s) / 4 / sigma^2) over the chirps' scale factors."""
    g = np.random.default_rng(2)
    lsb = 1 / cl.HWA_OUTPUT_SCALE
    rf = (g.standard_normal((n_c, 4, 192)) + 1j * g.standard_normal((n_c, 4, 192))) * sigma * lsb
    c = np.arange(n_c)
    rf[:, :, 35] += 10 * sigma * lsb * np.exp(2j * np.pi * 25 / n_c * c)[:, None]
    strong = 10 * sigma * lsb * 10 ** (diff_db / 20) * np.exp(2j * np.pi * 77 / n_c * c)[:, None]
    for b, w in ((32, 0.5), (33, 1.0), (34, 0.5)):
        rf[:, :, b] += w * strong
    rf = rf.astype(np.complex64)

    def snr(x):
        p = np.abs(np.fft.fft(x[:, :, 35], axis=0)) ** 2
        floor = np.delete(p, [25], axis=0).mean()
        return 10 * np.log10((p[25].mean() - floor) / floor)

    out, shift = cl.ege_compress(rf.copy())
    model = 10 * np.log10(1 + np.mean(4.0 ** shift[:, 4]) / 4 / sigma ** 2)
    return int(np.median(shift[:, 4])), snr(rf) - snr(out), model


def _interleaved(f_a, f_b, repeats: int, warmup: int) -> tuple[float, float]:
    """Medians of two callables timed alternately (load changes hit both alike), s."""
    for _ in range(warmup):
        f_a(), f_b()
    ta, tb = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f_a()
        t1 = time.perf_counter()
        f_b()
        ta.append(t1 - t0)
        tb.append(time.perf_counter() - t1)
    return float(np.median(ta)), float(np.median(tb))


class _LowrankWork(NamedTuple):
    """The default repair ("lowrank") of one frame's flagged rows, as the benches time it."""

    rows: np.ndarray                      # (R,) flagged chirp x Rx rows
    bursts: np.ndarray                    # (R,) their chirps
    basis: FastTimeBasis                  # the frame's fast-time basis
    reference_and_basis: Callable[[], FastTimeBasis]  # reference rows + basis, recomputed
    fill: Callable[[float], None]         # the fill with this grow_sigma, on a copy of the rows


def _lowrank_work(cfg, adc: np.ndarray, stats, proc, remove_mean: bool) -> _LowrankWork:
    """`_LowrankWork` of `adc` (int16 frame) with its chirp statistics ``stats`` (dc, rows,
    flags: `chirp_statistics`): the DC-removed rows, the reference rows (the repaired rows'
    masks only if the frame has too few clean rows) and the fill's settings, as the repair
    computes them."""
    m = MITIGATIONS["lowrank"]
    n = cfg.n_samples
    dc, rows, flags = stats
    y = np.subtract(adc.reshape(-1, n)[rows], dc.reshape(-1, 1)[rows], dtype=np.float32)
    frame = FrameRows(adc.reshape(-1, n), rows, cfg.n_rx)
    gate = 10 ** (m.rank_snr_gate_db / 10)

    def reference_and_basis():
        return fast_time_basis(reference_rows(
            y, frame, lambda: m.mask(flags, proc.interference.hysteresis_samples)), m.rank_max,
            gate)
    basis = reference_and_basis()
    bursts = rows // cfg.n_rx
    hw = proc.interference.hysteresis_samples + m.extend_samples

    def fill(grow_sigma: float) -> None:
        lowrank_fill(y.copy(), flags, bursts, basis, m.close_gap_samples, hw, grow_sigma,
                     m.grow_reach_samples, remove_mean=remove_mean)
    return _LowrankWork(rows, bursts, basis, reference_and_basis, fill)


def lowrank_breakdown(cfg, adc: np.ndarray, repeats: int, warmup: int) -> list[str]:
    """Where the default repair ("lowrank") spends its time on the frame: thread CPU of the
    frame's fast-time basis and of the fill (one part: `pipeline.threads.inline`) with and
    without the mask growth, and the work's size (hit rows and chirps, components). The basis
    and the fill's row projections are BLAS calls: with several BLAS threads on a busy
    machine, this thread's time includes OpenBLAS waiting for its worker threads."""
    proc = pipeline.ProcessingConfig()
    rows, bursts, basis, reference_and_basis, fill_rows = _lowrank_work(
        cfg, adc, chirp_statistics(adc, proc), proc, remove_mean=True)

    def fill(grow_sigma):
        with inline():
            fill_rows(grow_sigma)

    grow = MITIGATIONS["lowrank"].grow_sigma
    t_basis = median_time_s(reference_and_basis, repeats, warmup, clock=time.thread_time)
    t_fill = median_time_s(lambda: fill(grow), repeats, warmup, clock=time.thread_time)
    t_fixed = median_time_s(lambda: fill(0.0), repeats, warmup, clock=time.thread_time)
    return [f"  lowrank on this frame: {rows.size} hit rows of {adc.shape[0] * adc.shape[1]}, "
            f"{np.unique(bursts).size} hit chirps, k = {basis.vectors.shape[1]} components; "
            f"thread CPU (one part): reference rows + basis {1e3 * t_basis:.2f} ms, fill "
            f"{1e3 * t_fill:.2f} ms (of which mask growth and refits "
            f"{1e3 * (t_fill - t_fixed):.2f} ms)"]


def _alternating_cpu(fns: dict, repeats: int, warmup: int) -> dict[str, float]:
    """Median thread CPU of each callable, s, timed in alternating rounds (load hits all
    alike)."""
    for fn in fns.values():
        for _ in range(warmup):
            fn()
    times = {k: [] for k in fns}
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.thread_time()
            fn()
            times[k].append(time.thread_time() - t0)
    return {k: float(np.median(v)) for k, v in times.items()}


def dirty_frame_breakdown(repeats: int, warmup: int) -> list[str]:
    """Where the 10-interferer DDMA frame of `benchmarks.bench_floors` (its "ddma, 10
    interferers" row) spends what the clean frame does not: the work (thread CPU, one part:
    `pipeline.threads.inline`) of the whole frame and of the range stage's pieces, clean and
    dirty, alternated; then, in two parts, the calling thread's CPU (the serial share, which
    bounds the wall time on an idle machine from below) and the wall time."""
    cfg = radarsim.presets.r79_ddma()
    sc = _scene(N_SCATTERERS)  # bench_floors' scene (the same draws), its frames
    frames = {"clean": radarsim.simulate_frame(cfg, sc, np.random.default_rng(0)),
              "dirty": radarsim.simulate_frame(cfg, sc, np.random.default_rng(0),
                                               interferers(N_INTERFERERS))}
    proc = pipeline.ProcessingConfig()
    m = MITIGATIONS[proc.interference.repair]
    n = cfg.n_samples
    win = window(WINDOWS[proc.range.window], n)
    w = window(WINDOWS[proc.doppler.window], cfg.n_chirps)
    stats = {k: chirp_statistics(a, proc) for k, a in frames.items()}
    dc, rows, flags = stats["dirty"]
    adc = frames["dirty"]
    rep = repaired_rows(adc, dc, rows, flags, win, proc.interference)
    # as repaired_rows calls the fill: the means left to the window pass
    work = _lowrank_work(cfg, adc, stats["dirty"], proc, remove_mean=False)

    fns = {}
    for k, a in frames.items():
        fns[f"frame {k}"] = lambda a=a: pipeline.process_frame(cfg, a)
        fns[f"stage {k}"] = lambda a=a: cl.windowed_range_stage(cfg, a, proc, w)
        fns[f"stats {k}"] = lambda a=a: chirp_statistics(a, proc)
        fns[f"blocks {k}"] = lambda a=a, d=stats[k][0], r=(rep if k == "dirty" else None): \
            blockwise_range_stage(cfg, a, proc, d, w, None, r)
    # the chip's statistics alone, then the search for the weak bursts it missed
    intf = proc.interference
    _, chip_rows, chip_flags = chirp_statistics(adc, proc.replace(
        **{"interference.weak_burst_snr_db": None}))
    fns["weak bursts"] = lambda: with_weak_bursts(adc, dc, chip_rows, chip_flags,
                                                  intf.weak_burst_snr_db,
                                                  intf.weak_burst_window_samples)
    fns["repaired rows"] = lambda: repaired_rows(adc, dc, rows, flags, win, proc.interference)
    fns["basis"] = work.reference_and_basis
    fns["fill"] = lambda: work.fill(m.grow_sigma)
    fns["fill, no growth"] = lambda: work.fill(0.0)
    with inline():
        t = {k: 1e3 * v for k, v in _alternating_cpu(fns, repeats, warmup).items()}
    # two parts: the calling thread's CPU and the wall time
    serial = {k: ([], []) for k in frames}
    for _ in range(repeats):
        for k, a in frames.items():
            t0, w0 = time.thread_time(), time.perf_counter()
            pipeline.process_frame(cfg, a)
            serial[k][0].append(time.thread_time() - t0)
            serial[k][1].append(time.perf_counter() - w0)
    ms = {k: [1e3 * float(np.median(v)) for v in vv] for k, vv in serial.items()}

    def extra(what):
        return t[f"{what} dirty"] - t[f"{what} clean"]
    rest = extra("frame") - extra("stage")
    other = t["repaired rows"] - t["basis"] - t["fill"]
    return [
        f"dirty-frame breakdown (bench_floors' DDMA frame + {N_INTERFERERS} interferers: "
        f"{rows.size} of {adc.shape[0] * adc.shape[1]} rows flagged, "
        f"{np.unique(rows // cfg.n_rx).size} chirps hit, k = {work.basis.vectors.shape[1]}):",
        f"  work (thread CPU, one part): clean {t['frame clean']:.2f} ms, dirty "
        f"{t['frame dirty']:.2f} ms = +{extra('frame'):.2f} ms "
        f"({t['frame dirty'] / t['frame clean']:.2f}x)",
        f"    range stage +{extra('stage'):.2f} ms (pieces timed on their own: the rest is "
        "a difference, noise included): statistics and flags "
        f"+{extra('stats'):.2f} (of which the weak-burst search {t['weak bursts']:.2f}), "
        f"repaired rows {t['repaired rows']:.2f} (reference rows + "
        f"basis {t['basis']:.2f}, lowrank fill {t['fill']:.2f} of which mask growth "
        f"{t['fill'] - t['fill, no growth']:.2f}, DC removal, row means and the rest "
        f"{other:.2f}), "
        f"blockwise window / rFFT / EGE +{extra('blocks'):.2f}",
        f"    the rest of the chain (Doppler, maps, CFAR...) {rest:+.2f} ms",
        f"  two parts: calling thread's CPU clean {ms['clean'][0]:.2f} ms, dirty "
        f"{ms['dirty'][0]:.2f} ms (+{ms['dirty'][0] - ms['clean'][0]:.2f}: the serial share "
        f"bounds the wall from below); wall clean {ms['clean'][1]:.2f} ms, dirty "
        f"{ms['dirty'][1]:.2f} ms ({ms['dirty'][1] / ms['clean'][1]:.2f}x)"]


def run(repeats: int = 15, warmup: int = 2) -> list[str]:
    cfg = radarsim.presets.r79_ddma()
    sc = _scene(N_SCATTERERS)
    itf = interferers(N_INTERFERERS)
    out = np.zeros((cfg.n_chirps * cfg.n_rx, cfg.n_samples), np.float32)
    rng = np.random.default_rng(0)
    t_sim = median_time_s(lambda: radarsim.simulate_frame(cfg, sc, rng), repeats, warmup)
    t_itf = median_time_s(lambda: itf_mod.synthesize(cfg, itf, out=out), repeats, warmup)
    n_burst = int(itf_mod.burst_windows(cfg, itf)["n_samples"].sum())
    clean = radarsim.simulate_frame(cfg, sc, rng)
    adc = radarsim.simulate_frame(cfg, sc, rng, itf)
    on, off = pipeline.ProcessingConfig(), pipeline.ProcessingConfig().replace(**CHAIN_OFF)
    # The ratio is the figure with a target: twice the repeats, alternated (load hits both).
    t_off, t_on = _interleaved(lambda: pipeline.process_frame(cfg, clean, off),
                               lambda: pipeline.process_frame(cfg, clean, on), 2 * repeats + 1,
                               warmup)
    ti_off, ti_on = _interleaved(lambda: pipeline.process_frame(cfg, adc, off),
                                 lambda: pipeline.process_frame(cfg, adc, on), repeats, warmup)
    t_stage = {k: median_time_s(lambda p=p: cl.range_stage(cfg, adc, p), repeats, warmup)
               for k, p in (("range FFT only", off),
                            ("+ DC removal", pipeline.ProcessingConfig().replace(
                                **{"interference.repair": "off",
                                   "compression.enabled": False})),
                            ("+ mitigation",
                             pipeline.ProcessingConfig().replace(
                                 **{"compression.enabled": False})),
                            ("+ EGE compression (all)", on))}
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines = [f"machine: {os.cpu_count()} cpus, 1-min load average {load:.2f}",
             f"simulate_frame r79_ddma K={N_SCATTERERS}: median {1e3 * t_sim:.2f} ms",
             f"interference synthesis, {N_INTERFERERS} interferers ({n_burst} burst samples "
             f"x {cfg.n_rx} Rx): median {1e3 * t_itf:.2f} ms = {t_itf / t_sim:.2f} x "
             f"simulate_frame (target <= 1: {'met' if t_itf <= t_sim else 'MISSED'})",
             f"process_frame r79_ddma, K={N_SCATTERERS} frame: chirp-level chain off "
             f"{1e3 * t_off:.2f} ms, on (R79 demo defaults) {1e3 * t_on:.2f} ms = "
             f"+{100 * (t_on / t_off - 1):.0f} % (target <= +30 %: "
             f"{'met' if t_on <= 1.3 * t_off else 'MISSED'})",
             f"process_frame r79_ddma, same frame + {N_INTERFERERS} interferers: off "
             f"{1e3 * ti_off:.2f} ms, on {1e3 * ti_on:.2f} ms = +{100 * (ti_on / ti_off - 1):.0f} %"
             " (flagged chirps zeroed before the one range FFT; half the EGE blocks hot)"]
    lines += [f"  range stage {k}: {1e3 * v:.2f} ms" for k, v in t_stage.items()]
    # What each repair method costs on the same frame (the range stage without compression).
    base = pipeline.ProcessingConfig().replace(**{"compression.enabled": False})
    t_rep = {name: median_time_s(
        lambda p=base.replace(**{"interference.repair": name}): cl.range_stage(cfg, adc, p),
        repeats, warmup) for name in MITIGATIONS}
    lines += [f"  range stage, mitigation {k!r}: {1e3 * v:.2f} ms (+{1e3 * (v - t_rep['zero']):.2f}"
              " ms over the chip's zero)" for k, v in t_rep.items()]
    lines += lowrank_breakdown(cfg, adc, repeats, warmup)
    lines += dirty_frame_breakdown(repeats, warmup)
    # What the chain does to one interferer's floor (short and long bursts).
    empty = radarsim.Scatterers.empty()
    for slope, what in ((50e12, "short bursts, |dS| = 41 MHz/us"),
                        (15e12, "long bursts, |dS| = 6 MHz/us")):
        one = itf_mod.Interferers(position_m=[[15.0, 5.0, 0.0]], radial_velocity_mps=[-5.0],
                                  tx_gain_dbi=[10.0], start_freq_hz=[77.02e9],
                                  slope_hz_per_s=[slope], chirp_period_s=[31e-6],
                                  ramp_time_s=[25e-6], chirp_offset_s=[2e-6],
                                  tx_power_dbm=[15.0])
        a = radarsim.simulate_frame(cfg, empty, np.random.default_rng(6), one)
        inr = itf_mod.interference_to_noise_db(cfg, one)
        f_off = cl.noise_floor_rise(cfg, a, pipeline.ProcessingConfig().replace(
            **{"interference.repair": "off"})).doppler_db
        f_on = cl.noise_floor_rise(cfg, a, on).doppler_db
        lines.append(f"one interferer at 15.8 m ({what}), INR {inr:.1f} dB: floor rise after "
                     f"the Doppler FFT {f_off:.1f} dB without mitigation, {f_on:.1f} dB with")
    for diff in (30.0, 50.0, 60.0, 70.0):
        s, loss, model = _weak_next_to_strong(diff)
        lines.append(f"EGE 50 %: weak target (10 sigma) {diff:.0f} dB below a strong one in "
                     f"its block: scale factor {s} (median), SNR loss {loss:.2f} dB "
                     f"(model 10 log10(1 + mean 4^s / 4 / sigma^2) = {model:.2f} dB)")
    return lines
