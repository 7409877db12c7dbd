"""Waveform comparison of every registered MIMO scheme on the same randomized point targets
([TI-DDMA] section 3.2, table 1 and the paragraph after figure 4, made numbers).

One table, one row per `radarsim.MIMO_SCHEMES` entry: detection-SNR gain over TDMA on the same
targets (noise-limited, TDMA at 17-24 dB), velocity-resolution failure rate (velocity off by a
non-zero multiple of the scheme's failure step) at 14 / 17 / 20 dB detection SNR, range /
velocity / azimuth RMSE at 20 dB against the CRB of design.md 8, and the process_frame median as a
ratio to the rFFT + Doppler FFT floor of the same scheme measured in the same run. Then BPM's
residual cross-Tx leakage versus radial speed, beyond its Vmax = 10.2 m/s too: decoded at the
chain's velocity, and decoded without Doppler compensation.

    python -m benchmarks schemes        # this table only
"""
from __future__ import annotations

import sys

import numpy as np

import pipeline
import radarsim
from pipeline.mimo.bpm import bpm_decode
from pipeline.mimo.tdma import slot_maps

from ._timing import ChainTiming, chain_against_floor

HANN_LOSS_DB = 1.76
N_TARGETS = 40
SNRS_DB = (14.0, 17.0, 20.0)


def _coherent_gain_db(cfg) -> float:
    """Range + Doppler + 12-element azimuth coherent gains minus two Hann losses, dB; the
    Doppler gain counts the chirps whose energy each Tx contributes (its transmit code)."""
    chirps = float(np.sum(cfg.scheme.transmit_code(cfg).gain[0] ** 2))
    return (10 * np.log10(cfg.n_samples / 2) + 10 * np.log10(chirps) + 10 * np.log10(12)
            - 2 * HANN_LOSS_DB)


def scene_at_detection_snr(cfg, t) -> radarsim.Scatterers:
    """Targets (range_m, az_deg, el_deg, v_mps, detection_snr_db) -> Scatterers at that SNR."""
    t = np.atleast_2d(np.asarray(t, float))
    unit = radarsim.Scatterers.from_spherical(*t[:, :4].T, np.ones(len(t)))
    s1 = radarsim.expected_sample_snr_db(cfg, unit)
    rcs = 10 ** ((t[:, 4] - s1 - _coherent_gain_db(cfg)) / 10)
    return radarsim.Scatterers.from_spherical(*t[:, :4].T, rcs)


def _best(pc, r):
    near = pc[(pc.range_m - r).abs() < 2.0]
    return None if near.empty else near.loc[near.snr_db.idxmax()]


def _targets(rng, n, snr_db):
    return np.column_stack([rng.uniform(10, 200, n), rng.uniform(-60, 60, n),
                            rng.uniform(-15, 15, n), rng.uniform(-40.5, 40.5, n),
                            np.full(n, snr_db)])


def crb(cfg, snr_db: float) -> tuple[float, float, float]:
    """design.md 8 (rectangular window): sigma_R = dR sqrt(3) / (pi sqrt(2 SNR)), the same form
    for velocity (dv) and for sin(az) of the 12-element lambda/2 row (2/12), m, m/s, deg."""
    k = np.sqrt(3) / (np.pi * np.sqrt(2 * 10 ** (snr_db / 10)))
    return (cfg.range_resolution_m * k, cfg.velocity_resolution_mps * k,
            np.degrees(2 / 12 * k))


def _scheme_row(name: str, rng) -> dict:
    cfg = radarsim.presets.r79(name, array={"antenna_pattern": "isotropic"})
    step = cfg.scheme.velocity_failure_step_mps(cfg)
    row = {"scheme": name, "vmax": cfg.max_unambiguous_velocity_mps}
    for snr in SNRS_DB:
        fails = found = 0
        err = []
        for r, az, el, v, s in _targets(rng, N_TARGETS, snr):
            adc = radarsim.simulate_frame(cfg, scene_at_detection_snr(cfg, [r, az, el, v, s]),
                                          rng)
            b = _best(pipeline.process_frame(cfg, adc), r)
            if b is None:
                continue
            found += 1
            dv = b.radial_velocity_mps - v
            k = np.rint(dv / step)
            if k != 0 and abs(dv - k * step) < 1.0:
                fails += 1
            elif abs(dv) < 1.0:
                err.append((b.range_m - r, dv, b.azimuth_deg - az))
        row[f"fail_{snr:g}"] = fails / found if found else np.nan
        row[f"found_{snr:g}"] = found
        if snr == 20.0:
            e = np.array(err)
            row["rmse"] = np.sqrt(np.mean(e ** 2, axis=0)) if len(e) else np.full(3, np.nan)
    row["t"] = timing(name)
    return row


def timing(name: str) -> ChainTiming:
    """process_frame against the FFT floor on a five-target scene of scheme `name`
    (`_timing.chain_against_floor`: best of alternating rounds, CPU against the one-core
    floor, wall against the all-core floor)."""
    cfg = radarsim.presets.r79(name, array={"antenna_pattern": "isotropic"})
    sc = scene_at_detection_snr(cfg, [[15, 20, 0, -12, 40], [45, -30, 2, 15, 40],
                                      [90, 5, 0, -30, 30], [150, 40, -3, 5, 25],
                                      [60, -10, 0, 8, 30]])
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(0))
    return chain_against_floor(cfg, adc)


def _snr_gain_over(base: str, names, rng, n: int = 30) -> dict[str, float]:
    """Median snr_db(scheme) - snr_db(base) over the same noise-limited targets (base at
    17-24 dB), each scheme its own noise."""
    cfgs = {m: radarsim.presets.r79(m, array={"antenna_pattern": "isotropic"}) for m in names}
    gains = {m: [] for m in names}
    for _ in range(n):
        tg = [rng.uniform(20, 200), rng.uniform(-45, 45), 0.0, rng.uniform(-9, 9),
              rng.uniform(17, 24)]
        sc = scene_at_detection_snr(cfgs[base], tg)
        snr = {}
        for m, c in cfgs.items():
            b = _best(pipeline.process_frame(c, radarsim.simulate_frame(c, sc, rng)), tg[0])
            snr[m] = np.nan if b is None else b.snr_db
        for m in names:
            gains[m].append(snr[m] - snr[base])
    return {m: float(np.nanmedian(g)) for m, g in gains.items()}


def bpm_leakage_dbc(v_mps: float, rng, compensate: bool = True) -> float:
    """Residual cross-Tx leakage of BPM's decoded virtual array for one strong target at
    radial speed `v_mps` (20 deg azimuth, 5 deg elevation, 50 m), dBc: energy off the array's
    steering vector over the energy on it. Decoded after removing the Doppler phase at the
    velocity the chain reports (its disambiguation), or without compensation."""
    cfg = radarsim.presets.r79("bpm", array={"antenna_pattern": "isotropic"})
    r = 50.0
    sc = radarsim.Scatterers.from_spherical(np.array([r]), np.array([20.0]), np.array([5.0]),
                                            np.array([v_mps]), np.array([1e5]))
    adc = radarsim.simulate_frame(cfg, sc, rng)
    b = _best(pipeline.process_frame(cfg, adc), r)
    v_hat = b.radial_velocity_mps if (b is not None and compensate) else 0.0
    maps = slot_maps(cfg, adc, pipeline.ProcessingConfig())
    rb = int(b.range_bin) if b is not None else int(np.argmax(maps.power.max(axis=1)))
    db = int(np.argmax(maps.power[rb]))
    slots = maps.virt[rb, db].reshape(cfg.n_tx, cfg.n_rx)
    comp = np.exp(2j * np.pi * (2 * v_hat / cfg.wavelength_m) * np.arange(cfg.n_tx)
                  * cfg.chirp_period_s)
    x = bpm_decode(cfg.scheme.code_matrix(cfg), slots * comp[:, None]).reshape(-1)
    steer = np.exp(2j * np.pi / cfg.wavelength_m * cfg.virtual_positions_m @ sc.unit_vector[0])
    a = np.vdot(steer, x) / cfg.n_virtual
    return float(10 * np.log10(np.sum(np.abs(x - a * steer) ** 2)
                               / np.sum(np.abs(a * steer) ** 2)))


def run() -> list[str]:
    rng = np.random.default_rng(2026)
    names = sorted(radarsim.MIMO_SCHEMES)
    base = "tdma"
    gain = _snr_gain_over(base, names, rng)
    rows = [_scheme_row(m, rng) for m in names]
    bound = crb(radarsim.presets.r79(base), 20.0)
    out = [f"{N_TARGETS} random targets per SNR (10-200 m, az +/-60 deg, el +/-15 deg, "
           "v +/-40.5 m/s), isotropic elements; failure = velocity off by a non-zero "
           "multiple of the scheme's step (of the detected targets)",
           f"CRB at 20 dB (design.md 8): range {100 * bound[0]:.1f} cm, velocity "
           f"{1e3 * bound[1]:.1f} mm/s, azimuth {bound[2]:.2f} deg",
           f"{'scheme':<13}{'Vmax m/s':>9}{'gain dB':>9}{'fail@14':>9}{'fail@17':>9}"
           f"{'fail@20':>9}{'dR cm':>8}{'dv mm/s':>9}{'daz deg':>9}{'ms':>7}{'floor':>7}"
           f"{'ratio':>7}{'cpu ms':>8}{'cpu fl':>8}{'cpu ratio':>10}"]
    for w in rows:
        rm = w["rmse"]
        out.append(f"{w['scheme']:<13}{w['vmax']:>9.2f}{gain[w['scheme']]:>9.2f}"
                   f"{w['fail_14']:>9.3f}{w['fail_17']:>9.3f}{w['fail_20']:>9.3f}"
                   f"{100 * rm[0]:>8.1f}{1e3 * rm[1]:>9.1f}{rm[2]:>9.2f}"
                   f"{1e3 * w['t'].chain.wall_s:>7.1f}{1e3 * w['t'].floor_wall_s:>7.1f}"
                   f"{w['t'].wall_ratio:>6.1f}x"
                   f"{1e3 * w['t'].chain.cpu_s:>8.1f}{1e3 * w['t'].floor_cpu_s:>8.1f}"
                   f"{w['t'].cpu_ratio:>9.1f}x")
    if "bpm" in radarsim.MIMO_SCHEMES:
        speeds = (0.0, 2.0, 5.0, 10.0, 15.0, 25.0, 40.0)
        lk = [bpm_leakage_dbc(v, np.random.default_rng(int(v) + 1)) for v in speeds]
        raw = [bpm_leakage_dbc(v, np.random.default_rng(int(v) + 1), compensate=False)
               for v in speeds]
        out.append("BPM cross-Tx leakage vs radial speed (Vmax 10.22 m/s), dBc: "
                   + ", ".join(f"{v:g} m/s {x:.1f}" for v, x in zip(speeds, lk)))
        out.append("BPM leakage decoded without Doppler compensation, dBc: "
                   + ", ".join(f"{v:g} m/s {x:.1f}" for v, x in zip(speeds, raw)))
    return out


if __name__ == "__main__":
    from harness.runtime import tune_allocator
    tune_allocator()
    if "--timing" in sys.argv:  # the speed columns only
        for m in sorted(radarsim.MIMO_SCHEMES):
            t = timing(m)
            print(f"{m:<13} cpu {1e3 * t.chain.cpu_s:6.1f} ms / one-core floor "
                  f"{1e3 * t.floor_cpu_s:5.1f} ms = {t.cpu_ratio:4.1f}x; wall "
                  f"{1e3 * t.chain.wall_s:6.1f} / {1e3 * t.floor_wall_s:5.1f} ms = "
                  f"{t.wall_ratio:4.1f}x", flush=True)
    else:
        for line in run():
            print(line, flush=True)
